// convertRawlogToBag (rawlog2bag.h): the rawlog is read one observation at a time; each becomes one message, stamped
// (header and bag time) with the observation's time in nanoseconds.
#include <geometry_msgs/PoseStamped.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>
#include <rosbag/bag.h>
#include <sensor_msgs/Imu.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/dataset/calibration.h>
#include <quasiloc/dataset/kalibr.h>
#include <quasiloc/dataset/rawlog_writer.h>
#include <quasiloc/dataset/timestamps.h>
#include <quasiloc/ros/bag_images.h>
#include <quasiloc/ros/rawlog2bag.h>

namespace fs = std::filesystem;
using quasiloc::core::InputError;
using quasiloc::core::require;

namespace quasiloc::ros
{
namespace
{
::ros::Time rosTime(std::int64_t t_ns)
{
    ::ros::Time t;
    t.fromNSec(std::uint64_t(t_ns));
    return t;
}

class BagWriter
{
   public:
    BagWriter(const Rawlog2BagOptions& o, const dataset::SensorCalibration& calib, const std::string& tmp_bag)
        : o_(o), calib_(calib)
    {
        try
        {
            bag_.open(tmp_bag, rosbag::bagmode::Write);
            bag_.setCompression(o.compression == BagCompression::Bz2   ? rosbag::compression::BZ2
                                : o.compression == BagCompression::Lz4 ? rosbag::compression::LZ4
                                                                       : rosbag::compression::Uncompressed);
        }
        catch (const rosbag::BagException& e)
        {
            throw InputError(o.output_bag, std::string("cannot write the bag: ") + e.what());
        }
    }

    void stereo(std::int64_t t_ns, const cv::Mat& left, const cv::Mat& right)
    {
        image(o_.left_topic, "cam0", t_ns, left);
        image(o_.right_topic, "cam1", t_ns + std::llround(o_.right_delay_ms * 1e6), right);
        ++r.stereo_written;
    }

    void imu(std::int64_t t_ns, const mrpt::obs::CObservationIMU& obs)
    {
        using namespace mrpt::obs;
        sensor_msgs::Imu msg;
        msg.header.stamp = rosTime(t_ns);
        msg.header.frame_id = "imu0";
        msg.header.seq = seq_imu_++;
        msg.orientation_covariance[0] = -1;  // no orientation
        msg.linear_acceleration.x = obs.get(IMU_X_ACC);
        msg.linear_acceleration.y = obs.get(IMU_Y_ACC);
        msg.linear_acceleration.z = obs.get(IMU_Z_ACC);
        msg.angular_velocity.x = obs.get(IMU_WX);
        msg.angular_velocity.y = obs.get(IMU_WY);
        msg.angular_velocity.z = obs.get(IMU_WZ);
        bag_.write(o_.imu_topic, msg.header.stamp, msg);
        ++r.imu_written;
    }

    /** T_world_cam0 poses become PoseStamped of the body (IMU) frame in "world". */
    void groundTruth(const core::Trajectory& gt)
    {
        std::uint32_t seq = 0;
        for (const auto& p : gt.poses)
        {
            const mrpt::poses::CPose3D T_world_body = p.pose + (-calib_.rig.T_body_left);
            const Eigen::Quaterniond q = core::quaternionOf(T_world_body);
            geometry_msgs::PoseStamped msg;
            msg.header.stamp = rosTime(dataset::secondsToNs(p.t));
            msg.header.frame_id = "world";
            msg.header.seq = seq++;
            msg.pose.position.x = T_world_body.x();
            msg.pose.position.y = T_world_body.y();
            msg.pose.position.z = T_world_body.z();
            msg.pose.orientation.w = q.w();
            msg.pose.orientation.x = q.x();
            msg.pose.orientation.y = q.y();
            msg.pose.orientation.z = q.z();
            bag_.write(o_.groundtruth_topic, msg.header.stamp, msg);
            ++r.gt_written;
        }
    }

    void close() { bag_.close(); }

    Rawlog2BagResult r;

   private:
    void image(const std::string& topic, const char* frame, std::int64_t t_ns, const cv::Mat& gray)
    {
        const std::uint32_t seq = topic == o_.left_topic ? seq_left_++ : seq_right_++;
        if (o_.image_encoding == BagImageEncoding::Mono8 || o_.image_encoding == BagImageEncoding::Mono16)
        {
            sensor_msgs::Image msg = imageMsgFromGray(gray, o_.image_encoding == BagImageEncoding::Mono16);
            msg.header.stamp = rosTime(t_ns);
            msg.header.frame_id = frame;
            msg.header.seq = seq;
            bag_.write(topic, msg.header.stamp, msg);
        }
        else
        {
            sensor_msgs::CompressedImage msg =
                compressedMsgFromGray(gray, o_.image_encoding == BagImageEncoding::Png, o_.jpeg_quality);
            msg.header.stamp = rosTime(t_ns);
            msg.header.frame_id = frame;
            msg.header.seq = seq;
            bag_.write(topic, msg.header.stamp, msg);
        }
    }

    const Rawlog2BagOptions& o_;
    const dataset::SensorCalibration& calib_;
    rosbag::Bag bag_;
    std::uint32_t seq_left_ = 0, seq_right_ = 0, seq_imu_ = 0;
};

cv::Mat loadImage(const mrpt::img::CImage& img, const std::string& images_folder, const core::CameraModel& cam,
                  const std::string& where)
{
    cv::Mat gray;
    if (img.isExternallyStored())
    {
        const fs::path file(img.getExternalStorageFile());
        const std::string full = file.is_absolute() ? file.string() : (fs::path(images_folder) / file).string();
        require(fs::is_regular_file(full), full, "image file not found (" + where + ")");
        gray = cv::imread(full, cv::IMREAD_UNCHANGED);
        require(!gray.empty(), full, "cannot decode the image (" + where + ")");
    }
    else
        gray = img.asCvMat<cv::Mat>(mrpt::img::DEEP_COPY);
    require(gray.type() == CV_8UC1, where, "image is not 8-bit gray");
    require(gray.cols == cam.width && gray.rows == cam.height, where,
            "image is " + std::to_string(gray.cols) + "x" + std::to_string(gray.rows) + ", the calibration says " +
                std::to_string(cam.width) + "x" + std::to_string(cam.height));
    return gray;
}

void progressLine(bool enabled, std::uint64_t pos, std::uint64_t total, const Rawlog2BagResult& r, bool done,
                  int& shown)
{
    if (!enabled) return;
    const int percent = done ? 100 : total ? int(std::min<std::uint64_t>(99, 100 * pos / total)) : 0;
    if (percent / 10 == shown / 10 && !done) return;
    shown = percent;
    std::fprintf(stderr, "[%3d%%] %zu stereo frames, %zu IMU samples\n", percent, r.stereo_written, r.imu_written);
}
}  // namespace

Rawlog2BagResult convertRawlogToBag(const Rawlog2BagOptions& o)
{
    using namespace mrpt::obs;
    o.check();
    require(fs::is_regular_file(o.input_rawlog), o.input_rawlog, "rawlog file not found");
    const dataset::SensorCalibration calib = dataset::loadCalibration(o.calibration_ini);
    const dataset::ImuCalibration& imu = calib.requireImu(o.calibration_ini);
    core::Trajectory gt;
    if (!o.groundtruth.empty()) gt = core::readTum(o.groundtruth);

    core::StagedOutputs staged;
    const std::string tmp_bag = staged.addFile(o.output_bag);
    core::writeTextFileAtomically(
        staged.addFile(o.camchainPath()),
        "# Kalibr camchain written by rawlog2bag from " + o.calibration_ini + "\n" +
            dataset::kalibrCamchainText(calib.rig, o.left_topic, o.right_topic, o.calibration_ini));
    core::writeTextFileAtomically(staged.addFile(o.imuYamlPath()),
                                  "# Kalibr IMU noise model written by rawlog2bag from " + o.calibration_ini + "\n" +
                                      dataset::kalibrImuText(imu, o.imu_topic));

    BagWriter bag(o, calib, tmp_bag);
    mrpt::io::CFileGZInputStream in;
    require(in.open(o.input_rawlog), o.input_rawlog, "cannot open rawlog");
    const std::uint64_t total = fs::file_size(o.input_rawlog);
    auto arch = mrpt::serialization::archiveFrom(in);
    const std::string images_folder = dataset::rawlogImagesFolder(o.input_rawlog);
    int shown = -10;
    std::size_t entry = 0;
    const auto handle = [&](const CObservation::Ptr& obs, std::size_t at) {
        const std::int64_t t_ns = dataset::mrptTimeToNs(obs->timestamp);
        const std::string where = o.input_rawlog + " (entry " + std::to_string(at) + ")";
        if (auto stereo = std::dynamic_pointer_cast<CObservationStereoImages>(obs); stereo && stereo->hasImageRight)
            bag.stereo(t_ns, loadImage(stereo->imageLeft, images_folder, calib.rig.left, where + " left"),
                       loadImage(stereo->imageRight, images_folder, calib.rig.right, where + " right"));
        else if (auto i = std::dynamic_pointer_cast<CObservationIMU>(obs);
                 i && i->has(IMU_X_ACC) && i->has(IMU_Y_ACC) && i->has(IMU_Z_ACC) && i->has(IMU_WX) &&
                 i->has(IMU_WY) && i->has(IMU_WZ))
            bag.imu(t_ns, *i);
        else
            ++bag.r.ignored;
    };
    try
    {
        for (;;)
        {
            CActionCollection::Ptr action;
            CSensoryFrame::Ptr sf;
            CObservation::Ptr obs;
            const std::uint64_t pos_before = in.getPosition();
            const std::size_t at = entry;
            if (!CRawlog::getActionObservationPairOrObservation(arch, action, sf, obs, entry))
            {
                require(in.getPosition() == pos_before, o.input_rawlog,
                        "corrupt or truncated rawlog: cannot read entry " + std::to_string(at));
                break;
            }
            if (obs) handle(obs, at);
            if (sf)
                for (const auto& x : *sf) handle(x, at);
            progressLine(o.progress, in.getPosition(), total, bag.r, false, shown);
        }
        require(bag.r.stereo_written > 0, o.input_rawlog, "holds no CObservationStereoImages with a right image");
        bag.groundTruth(gt);
        bag.close();
    }
    catch (const rosbag::BagException& e)
    {
        throw InputError(o.output_bag, std::string("cannot write the bag: ") + e.what());
    }
    progressLine(o.progress, total, total, bag.r, true, shown);
    staged.commit();
    Rawlog2BagResult r = bag.r;
    r.bag_path = o.output_bag;
    r.camchain_path = o.camchainPath();
    r.imu_yaml_path = o.imuYamlPath();
    r.bag_bytes = fs::file_size(o.output_bag);
    return r;
}

}  // namespace quasiloc::ros
