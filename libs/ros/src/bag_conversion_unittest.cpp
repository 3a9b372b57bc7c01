// bag2rawlog on small bags written here: late right images, compressed images, every raw encoding, ground truth of
// each type, and the bad bags (a topic missing, an unknown encoding, a truncated file): each error names the topic
// or the file and leaves nothing behind. (ROS 1 bags: built when the library reads them.)
#ifdef QUASILOC_HAVE_ROS1
#include <geometry_msgs/TransformStamped.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/Imu.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <opencv2/imgproc.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/dataset/calibration.h>
#include <quasiloc/dataset/frame_source.h>
#include <quasiloc/dataset/kalibr.h>
#include <quasiloc/dataset/timestamps.h>
#include <quasiloc/ros/bag2rawlog.h>
#include <quasiloc/ros/bag_images.h>

#include "ros1/ros1_messages.h"

namespace fs = std::filesystem;
namespace core = quasiloc::core;
namespace dataset = quasiloc::dataset;
namespace qros = quasiloc::ros;

namespace
{
constexpr int kW = 64, kH = 48;
constexpr std::int64_t kT0 = 1403715273000000000LL;  // a Unix time in ns, as real bags have
constexpr std::int64_t kFramePeriod = 50000000, kImuPeriod = 5000000;

struct TempDir
{
    std::string path;
    TempDir()
    {
        std::string tmpl = (fs::temp_directory_path() / "quasiloc_ros_XXXXXX").string();
        if (!mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
        path = tmpl;
    }
    ~TempDir() { fs::remove_all(path); }
};

cv::Mat testImage(int i, bool right)
{
    cv::Mat img(kH, kW, CV_8UC1);
    for (int r = 0; r < kH; ++r)
        for (int c = 0; c < kW; ++c) img.at<uint8_t>(r, c) = uint8_t((r * 7 + c * 3 + i * 11 + (right ? 40 : 0)) % 256);
    return img;
}

::ros::Time rosTime(std::int64_t t_ns)
{
    ::ros::Time t;
    t.fromNSec(std::uint64_t(t_ns));
    return t;
}

/** How each image is written: by default mono8 raw images. */
using ImageWriter = std::function<void(rosbag::Bag&, const std::string& topic, std::int64_t t_ns, const cv::Mat&)>;

void writeRaw(rosbag::Bag& bag, const std::string& topic, std::int64_t t_ns, const cv::Mat& gray)
{
    sensor_msgs::Image msg = qros::ros1::toRos1(qros::imageMsgFromGray(gray, false));
    msg.header.stamp = rosTime(t_ns);
    bag.write(topic, msg.header.stamp, msg);
}

struct BagSpec
{
    int frames = 10;
    std::int64_t right_delay_ns = 0;
    ImageWriter left = writeRaw, right = writeRaw;
    std::string imu_topic = "/imu0";
    std::function<void(rosbag::Bag&, std::int64_t t_ns, int i)> groundtruth;
};

std::string writeBag(const std::string& path, const BagSpec& spec)
{
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    for (int i = 0; i < spec.frames; ++i)
    {
        const std::int64_t t = kT0 + i * kFramePeriod;
        for (std::int64_t k = 0; k < kFramePeriod / kImuPeriod; ++k)
        {
            sensor_msgs::Imu imu;
            imu.header.stamp = rosTime(t + k * kImuPeriod);
            imu.linear_acceleration.z = 9.81 + 0.001 * k;
            imu.angular_velocity.x = 0.01 * i;
            bag.write(spec.imu_topic, imu.header.stamp, imu);
        }
        spec.left(bag, "/cam0/image_raw", t, testImage(i, false));
        spec.right(bag, "/cam1/image_raw", t + spec.right_delay_ns, testImage(i, true));
        if (spec.groundtruth) spec.groundtruth(bag, t, i);
    }
    bag.close();
    return path;
}

qros::Bag2RawlogOptions optionsFor(const TempDir& dir, const std::string& bag)
{
    core::StereoRig rig;
    rig.left = rig.right = core::CameraModel::pinhole(kW, kH, 50, 50, 32, 24);
    rig.T_left_right = mrpt::poses::CPose3D(0.1, 0, 0, 0, 0, 0);
    rig.T_body_left = mrpt::poses::CPose3D(0.01, 0.02, 0.03, 0.1, 0.2, 0.3);
    std::ofstream(dir.path + "/camchain.yaml")
        << dataset::kalibrCamchainText(rig, "/cam0/image_raw", "/cam1/image_raw", "test");
    dataset::ImuCalibration imu;
    imu.gyroscope_noise_density = imu.gyroscope_random_walk = 1e-4;
    imu.accelerometer_noise_density = imu.accelerometer_random_walk = 1e-3;
    std::ofstream(dir.path + "/imu.yaml") << dataset::kalibrImuText(imu, "/imu0");
    qros::Bag2RawlogOptions o;
    o.input_bag = bag;
    o.output = dir.path + "/out/seq.rawlog";
    o.kalibr_camchain = dir.path + "/camchain.yaml";
    o.kalibr_imu = dir.path + "/imu.yaml";
    o.progress = false;
    return o;
}

std::string errorOf(const qros::Bag2RawlogOptions& o)
{
    try
    {
        qros::convertBagToRawlog(o);
    }
    catch (const core::InputError& e)
    {
        return e.what();
    }
    return "";
}

/** Nothing of the output: no rawlog, no images folder, no calibration, no temporary left over. */
void expectNothingWritten(const TempDir& dir)
{
    const fs::path out = dir.path + "/out";
    if (!fs::exists(out)) return;
    EXPECT_TRUE(fs::is_empty(out)) << "output left in " << out;
}
}  // namespace

TEST(BagConversion, RightImagesThreeMillisecondsLatePairWithTheirLeftImages)
{
    TempDir dir;
    BagSpec spec;
    spec.right_delay_ns = 3000000;
    auto o = optionsFor(dir, writeBag(dir.path + "/late.bag", spec));
    o.pair_tolerance_ms = 5;
    const auto r = qros::convertBagToRawlog(o);
    EXPECT_EQ(r.stereo_written, 10u);
    EXPECT_EQ(r.unpaired_left + r.unpaired_right, 0u);
    EXPECT_NEAR(r.max_pair_offset_ms, 3.0, 1e-9);
    EXPECT_EQ(r.imu_written, 100u);
    auto src = dataset::openRawlog(o.output, {{}, 0.005, r.calib_path});
    dataset::StereoFrame f;
    int n = 0;
    while (src->next(f))
    {
        // The left image's stamp (a double in seconds holds a Unix time to ~0.2 us).
        EXPECT_NEAR(double(dataset::secondsToNs(f.timestamp) - (kT0 + n * kFramePeriod)), 0.0, 500.0);
        EXPECT_EQ(cv::norm(f.left, testImage(n, false), cv::NORM_INF), 0);
        EXPECT_EQ(cv::norm(f.right, testImage(n, true), cv::NORM_INF), 0);
        ++n;
    }
    EXPECT_EQ(n, 10);
}

TEST(BagConversion, RightImagesLaterThanTheToleranceAreAnErrorNamingBothTopics)
{
    TempDir dir;
    BagSpec spec;
    spec.right_delay_ns = 3000000;
    auto o = optionsFor(dir, writeBag(dir.path + "/late.bag", spec));
    o.pair_tolerance_ms = 2;
    const std::string e = errorOf(o);
    EXPECT_NE(e.find("/cam0/image_raw and /cam1/image_raw"), std::string::npos) << e;
    EXPECT_NE(e.find("pair_tolerance_ms"), std::string::npos) << e;
    expectNothingWritten(dir);
}

TEST(BagConversion, CompressedPngAndJpegImagesAreRead)
{
    TempDir dir;
    BagSpec spec;
    const auto compressed = [](bool png) {
        return [png](rosbag::Bag& bag, const std::string& topic, std::int64_t t_ns, const cv::Mat& gray) {
            sensor_msgs::CompressedImage msg = qros::ros1::toRos1(qros::compressedMsgFromGray(gray, png, 95));
            msg.header.stamp = rosTime(t_ns);
            bag.write(topic, msg.header.stamp, msg);
        };
    };
    spec.left = compressed(true);
    spec.right = compressed(false);
    auto o = optionsFor(dir, writeBag(dir.path + "/compressed.bag", spec));
    const auto r = qros::convertBagToRawlog(o);
    EXPECT_EQ(r.left_type, "sensor_msgs/CompressedImage");
    EXPECT_EQ(r.stereo_written, 10u);
    auto src = dataset::openRawlog(o.output, {{}, 0.005, r.calib_path});
    dataset::StereoFrame f;
    ASSERT_TRUE(src->next(f));
    EXPECT_EQ(cv::norm(f.left, testImage(0, false), cv::NORM_INF), 0);             // png: lossless
    EXPECT_LT(cv::norm(f.right, testImage(0, true), cv::NORM_L1) / (kW * kH), 8);  // jpeg: close
}

TEST(BagConversion, EveryRawEncodingBecomesTheSameGrayImage)
{
    const cv::Mat gray = testImage(3, false);
    const std::string where = "test";
    qros::ImageMsg m16 = qros::imageMsgFromGray(gray, true);
    EXPECT_EQ(cv::norm(qros::grayFromImageMsg(m16, 8, where), gray, cv::NORM_INF), 0);
    cv::Mat bgr;
    cv::cvtColor(gray, bgr, cv::COLOR_GRAY2BGR);
    qros::ImageMsg color;
    color.width = kW;
    color.height = kH;
    color.step = kW * 3;
    color.data.assign(bgr.data, bgr.data + bgr.total() * 3);
    for (const char* enc : {"bgr8", "rgb8"})
    {
        color.encoding = enc;
        EXPECT_EQ(cv::norm(qros::grayFromImageMsg(color, 8, where), gray, cv::NORM_INF), 0) << enc;
    }
    color.encoding = "bayer_rggb8";
    EXPECT_THROW(qros::grayFromImageMsg(color, 8, where), core::InputError);
}

TEST(BagConversion, GroundTruthOfEachTypeBecomesTumOfTheLeftCamera)
{
    for (const std::string type : {"transform", "odometry"})
    {
        TempDir dir;
        BagSpec spec;
        spec.groundtruth = [type](rosbag::Bag& bag, std::int64_t t_ns, int i) {
            if (type == "transform")
            {
                geometry_msgs::TransformStamped m;
                m.header.stamp = rosTime(t_ns);
                m.transform.translation.x = i;
                m.transform.rotation.w = 1;
                bag.write("/gt", m.header.stamp, m);
            }
            else
            {
                nav_msgs::Odometry m;
                m.header.stamp = rosTime(t_ns);
                m.pose.pose.position.x = i;
                m.pose.pose.orientation.w = 1;
                bag.write("/gt", m.header.stamp, m);
            }
        };
        auto o = optionsFor(dir, writeBag(dir.path + "/gt.bag", spec));
        o.groundtruth_topic = "/gt";
        o.groundtruth_frame = qros::GroundTruthFrame::Cam0;
        const auto r = qros::convertBagToRawlog(o);
        EXPECT_EQ(r.gt_written, 10u) << type;
        const auto gt = core::readTum(r.gt_path);
        ASSERT_EQ(gt.poses.size(), 10u);
        EXPECT_NEAR(gt.poses[4].pose.x(), 4.0, 1e-12);
        EXPECT_EQ(dataset::secondsToNs(gt.poses[4].t) / 1000, (kT0 + 4 * kFramePeriod) / 1000);
    }
}

TEST(BagConversion, AMissingTopicIsAnErrorNamingItAndTheTopicsThere)
{
    TempDir dir;
    BagSpec spec;
    spec.imu_topic = "/imu_other";
    const auto o = optionsFor(dir, writeBag(dir.path + "/noimu.bag", spec));
    const std::string e = errorOf(o);
    EXPECT_NE(e.find("topic /imu0"), std::string::npos) << e;
    EXPECT_NE(e.find("/imu_other (sensor_msgs/Imu)"), std::string::npos) << e;
    expectNothingWritten(dir);
}

TEST(BagConversion, AnUnknownEncodingIsAnErrorNamingTheTopicAndTheEncoding)
{
    TempDir dir;
    BagSpec spec;
    spec.right = [](rosbag::Bag& bag, const std::string& topic, std::int64_t t_ns, const cv::Mat& gray) {
        sensor_msgs::Image msg = qros::ros1::toRos1(qros::imageMsgFromGray(gray, false));
        msg.encoding = "bayer_rggb8";
        msg.header.stamp = rosTime(t_ns);
        bag.write(topic, msg.header.stamp, msg);
    };
    const auto o = optionsFor(dir, writeBag(dir.path + "/bayer.bag", spec));
    const std::string e = errorOf(o);
    EXPECT_NE(e.find("topic /cam1/image_raw"), std::string::npos) << e;
    EXPECT_NE(e.find("'bayer_rggb8'"), std::string::npos) << e;
    expectNothingWritten(dir);
}

TEST(BagConversion, ATruncatedBagIsAnErrorNamingTheFile)
{
    TempDir dir;
    const std::string bag = writeBag(dir.path + "/cut.bag", BagSpec());
    fs::resize_file(bag, fs::file_size(bag) / 2);
    const std::string e = errorOf(optionsFor(dir, bag));
    EXPECT_NE(e.find("cut.bag"), std::string::npos) << e;
    expectNothingWritten(dir);
}
#endif  // QUASILOC_HAVE_ROS1
