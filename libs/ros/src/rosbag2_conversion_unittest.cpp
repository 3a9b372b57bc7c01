// bag2rawlog on small ROS 2 bags written here (MCAP through rawlog2bag's sink): the calibration from the bag's
// CameraInfo and /tf_static with the IMU noise model from an INI's [imu] section, and the bad bags (a CameraInfo of
// an unsupported distortion model, a topic of another type, a missing topic): each error names the file and the topic
// and leaves nothing behind.
#include <fstream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/dataset/calibration.h>
#include <quasiloc/ros/bag2rawlog.h>
#include <quasiloc/ros/bag_images.h>

#include "bag_sink.h"
#include "rosbag2_test_helpers.h"

namespace fs = std::filesystem;
using namespace quasiloc;
using namespace quasiloc::ros;
using namespace quasiloc::ros::test;

namespace
{
constexpr int kW = 64, kH = 48;
constexpr std::int64_t kT0 = 1700000000000000000LL, kFramePeriod = 50000000, kImuPeriod = 5000000;

struct Ros2BagSpec
{
    std::string distortion_model = "plumb_bob";
    std::vector<double> d = {0.01, -0.02, 0.001, 0.002, 0.0};
    bool left_as_imu = false;  ///< the left image topic holds sensor_msgs/Imu
};

cv::Mat testImage(int i, bool right)
{
    cv::Mat img(kH, kW, CV_8UC1);
    for (int r = 0; r < kH; ++r)
        for (int c = 0; c < kW; ++c) img.at<uint8_t>(r, c) = uint8_t((r * 5 + c * 3 + i * 13 + (right ? 60 : 0)) % 256);
    return img;
}

TransformMsg transform(const std::string& parent, const std::string& child, const mrpt::poses::CPose3D& T)
{
    TransformMsg t;
    t.header = {kT0, parent};
    t.child_frame_id = child;
    t.translation = {T.x(), T.y(), T.z()};
    t.rotation = core::quaternionOf(T);
    return t;
}

const mrpt::poses::CPose3D kT_base_imu(0.1, 0.0, 0.2, 0.0, 0.0, 0.0);
const mrpt::poses::CPose3D kT_base_cam0(0.15, 0.03, 0.25, -1.5707963, 0.0, -1.5707963);
const mrpt::poses::CPose3D kT_cam0_cam1(0.05, 0.0, 0.0, 0.0, 0.0, 0.0);

std::string writeRos2Bag(const std::string& folder, const Ros2BagSpec& spec)
{
    auto sink = makeMcapBagSink(folder, fs::path(folder).filename().string(), dataset::BagCompression::Zstd);
    // The extrinsics through a chain: base_link -> imu_link, base_link -> cam0 -> cam1.
    sink->tfStatic("/tf_static",
                   {transform("base_link", "imu_link", kT_base_imu), transform("base_link", "cam0", kT_base_cam0),
                    transform("cam0", "cam1", kT_cam0_cam1)});
    for (int i = 0; i < 8; ++i)
    {
        const std::int64_t t = kT0 + i * kFramePeriod;
        for (std::int64_t k = 0; k < kFramePeriod / kImuPeriod; ++k)
        {
            ImuMsg imu;
            imu.header = {t + k * kImuPeriod, "imu_link"};
            imu.linear_acceleration = {0, 0, 9.81};
            sink->imu(spec.left_as_imu && k == 0 ? "/cam0/image_raw" : "/imu0", imu);
        }
        for (const bool right : {false, true})
        {
            CameraInfoMsg info;
            info.header = {t, right ? "cam1" : "cam0"};
            info.width = kW;
            info.height = kH;
            info.distortion_model = spec.distortion_model;
            info.d = spec.d;
            info.k = {50, 0, 32, 0, 51, 24, 0, 0, 1};
            sink->cameraInfo(right ? "/cam1/camera_info" : "/cam0/camera_info", info);
            if (spec.left_as_imu && !right) continue;
            ImageMsg img = imageMsgFromGray(testImage(i, right), false);
            img.header = {t, right ? "cam1" : "cam0"};
            sink->image(right ? "/cam1/image_raw" : "/cam0/image_raw", img);
        }
    }
    sink->close();
    return folder;
}

Bag2RawlogOptions optionsFor(const TempDir& dir, const std::string& bag)
{
    std::ofstream(dir.path + "/imu.ini") << "[imu]\nrate_hz=200\ngyroscope_noise_density=1e-4\n"
                                            "gyroscope_random_walk=1e-5\naccelerometer_noise_density=1e-3\n"
                                            "accelerometer_random_walk=1e-4\n";
    Bag2RawlogOptions o;
    o.input_bag = bag;
    o.output = dir.path + "/out/seq.rawlog";
    o.imu_ini = dir.path + "/imu.ini";
    o.progress = false;
    return o;
}

void expectNothingWritten(const TempDir& dir)
{
    const bool empty = !fs::exists(dir.path + "/out") || fs::is_empty(dir.path + "/out");
    EXPECT_TRUE(empty) << "output left in " << dir.path << "/out";
}
}  // namespace

TEST(Rosbag2Conversion, TheCalibrationComesFromCameraInfoAndStaticTransforms)
{
    TempDir dir;
    const auto o = optionsFor(dir, writeRos2Bag(dir.path + "/bag", {}));
    const auto r = convertBagToRawlog(o);
    EXPECT_EQ(r.stereo_written, 8u);
    EXPECT_EQ(r.imu_written, 80u);
    EXPECT_EQ(r.bag_format, "rosbag2 mcap");
    const auto calib = dataset::loadCalibration(r.calib_path);
    EXPECT_EQ(calib.rig.left.width, kW);
    EXPECT_DOUBLE_EQ(calib.rig.left.fy, 51);
    EXPECT_EQ(calib.rig.left.model, core::DistortionModel::RadTan);
    EXPECT_DOUBLE_EQ(calib.rig.right.dist[1], -0.02);
    const mrpt::poses::CPose3D T_imu_cam0 = -kT_base_imu + kT_base_cam0;
    EXPECT_LT((calib.rig.T_body_left.asVectorVal() - T_imu_cam0.asVectorVal()).norm(), 1e-9);
    EXPECT_LT((calib.rig.T_left_right.asVectorVal() - kT_cam0_cam1.asVectorVal()).norm(), 1e-9);
    ASSERT_TRUE(calib.imu.has_value());
    EXPECT_DOUBLE_EQ(calib.imu->accelerometer_noise_density, 1e-3);
}

TEST(Rosbag2Conversion, AnUnsupportedDistortionModelIsAnErrorNamingTheFileTopicAndModel)
{
    TempDir dir;
    Ros2BagSpec spec;
    spec.distortion_model = "rational_polynomial";
    spec.d = {0.1, 0.01, 0, 0, 0, 0, 0, 0};
    const auto o = optionsFor(dir, writeRos2Bag(dir.path + "/bag", spec));
    const std::string e = errorOf([&] { convertBagToRawlog(o); });
    EXPECT_NE(e.find(dir.path + "/bag"), std::string::npos) << e;
    EXPECT_NE(e.find("topic /cam0/camera_info"), std::string::npos) << e;
    EXPECT_NE(e.find("'rational_polynomial'"), std::string::npos) << e;
    expectNothingWritten(dir);
}

TEST(Rosbag2Conversion, ATopicOfAnotherTypeOrMissingIsAnErrorNamingIt)
{
    TempDir dir;
    Ros2BagSpec spec;
    spec.left_as_imu = true;
    auto o = optionsFor(dir, writeRos2Bag(dir.path + "/bag", spec));
    std::string e = errorOf([&] { convertBagToRawlog(o); });
    EXPECT_NE(e.find("topic /cam0/image_raw"), std::string::npos) << e;
    EXPECT_NE(e.find("holds sensor_msgs/Imu"), std::string::npos) << e;
    expectNothingWritten(dir);
    o.left_topic = "/camera/left/image_raw";
    e = errorOf([&] { convertBagToRawlog(o); });
    EXPECT_NE(e.find("topic /camera/left/image_raw"), std::string::npos) << e;
    EXPECT_NE(e.find("not in the bag"), std::string::npos) << e;
    expectNothingWritten(dir);
}

TEST(Rosbag2Conversion, AMissingCameraInfoOrTransformIsAnErrorNamingTheTopic)
{
    TempDir dir;
    auto o = optionsFor(dir, writeRos2Bag(dir.path + "/bag", {}));
    o.right_camera_info_topic = "/cam1/info";
    std::string e = errorOf([&] { convertBagToRawlog(o); });
    EXPECT_NE(e.find("topic /cam1/info"), std::string::npos) << e;
    o.right_camera_info_topic.clear();
    o.imu_frame = "imu_optical";
    e = errorOf([&] { convertBagToRawlog(o); });
    EXPECT_NE(e.find("topic /tf_static"), std::string::npos) << e;
    EXPECT_NE(e.find("'imu_optical'"), std::string::npos) << e;
    expectNothingWritten(dir);
}
