// convertRawlogToBag (rawlog2bag.h): the rawlog is read one observation at a time; each becomes one message (plus,
// in a ROS 2 bag, a CameraInfo per image), stamped (header and bag time) with the observation's time in nanoseconds.
// The messages are built here once; a BagSink (bag_sink.h) writes them as ROS 1 or as ROS 2 MCAP.
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

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
#include <quasiloc/ros/message_source.h>
#include <quasiloc/ros/rawlog2bag.h>

#include "bag_sink.h"

namespace fs = std::filesystem;
using quasiloc::core::InputError;
using quasiloc::core::require;

namespace quasiloc::ros
{
namespace
{
const char* kTfStaticTopic = "/tf_static";
const char* kBodyFrame = "imu0";

/** The CameraInfo of a raw (unrectified) camera: K, D, R = I, P = [K | 0]. */
CameraInfoMsg cameraInfoOf(const core::CameraModel& cam, const MsgHeader& header)
{
    CameraInfoMsg m;
    m.header = header;
    m.width = std::uint32_t(cam.width);
    m.height = std::uint32_t(cam.height);
    m.distortion_model = cam.model == core::DistortionModel::Equidistant ? "equidistant" : "plumb_bob";
    if (cam.model == core::DistortionModel::RadTan) m.d.assign(cam.dist.begin(), cam.dist.end());
    if (cam.model == core::DistortionModel::Equidistant) m.d.assign(cam.dist.begin(), cam.dist.begin() + 4);
    m.k = {cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1};
    m.r = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    m.p = {cam.fx, 0, cam.cx, 0, 0, cam.fy, cam.cy, 0, 0, 0, 1, 0};
    return m;
}

TransformMsg transformOf(const mrpt::poses::CPose3D& T_parent_child, const std::string& parent,
                         const std::string& child, std::int64_t t_ns)
{
    TransformMsg t;
    t.header = {t_ns, parent};
    t.child_frame_id = child;
    t.translation = {T_parent_child.x(), T_parent_child.y(), T_parent_child.z()};
    t.rotation = core::quaternionOf(T_parent_child);
    return t;
}

class BagWriter
{
   public:
    BagWriter(const Rawlog2BagOptions& o, const dataset::SensorCalibration& calib, std::unique_ptr<BagSink> sink)
        : o_(o), calib_(calib), sink_(std::move(sink))
    {}

    void stereo(std::int64_t t_ns, const cv::Mat& left, const cv::Mat& right)
    {
        calibrationOnce(t_ns);
        const std::int64_t right_ns = t_ns + std::llround(o_.right_delay_ms * 1e6);
        image(o_.left_topic, "cam0", t_ns, left);
        image(o_.right_topic, "cam1", right_ns, right);
        if (sink_->carriesCalibration())
        {
            sink_->cameraInfo(o_.leftCameraInfoTopic(), cameraInfoOf(calib_.rig.left, {t_ns, "cam0"}));
            sink_->cameraInfo(o_.rightCameraInfoTopic(), cameraInfoOf(calib_.rig.right, {right_ns, "cam1"}));
        }
        ++r.stereo_written;
    }

    void imu(std::int64_t t_ns, const mrpt::obs::CObservationIMU& obs)
    {
        using namespace mrpt::obs;
        calibrationOnce(t_ns);
        ImuMsg msg;
        msg.header = {t_ns, kBodyFrame};
        msg.orientation.coeffs().setZero();  // no orientation (covariance[0] = -1 says so)
        msg.orientation_covariance[0] = -1;
        msg.linear_acceleration = {obs.get(IMU_X_ACC), obs.get(IMU_Y_ACC), obs.get(IMU_Z_ACC)};
        msg.angular_velocity = {obs.get(IMU_WX), obs.get(IMU_WY), obs.get(IMU_WZ)};
        sink_->imu(o_.imu_topic, msg);
        ++r.imu_written;
    }

    /** T_world_cam0 poses become PoseStamped of the body (IMU) frame in "world". */
    void groundTruth(const core::Trajectory& gt)
    {
        for (const auto& p : gt.poses)
        {
            const mrpt::poses::CPose3D T_world_body = p.pose + (-calib_.rig.T_body_left);
            PoseMsg msg;
            msg.header = {dataset::secondsToNs(p.t), "world"};
            msg.position = {T_world_body.x(), T_world_body.y(), T_world_body.z()};
            msg.orientation = core::quaternionOf(T_world_body);
            sink_->pose(o_.groundtruth_topic, msg);
            ++r.gt_written;
        }
    }

    void close() { sink_->close(); }

    Rawlog2BagResult r;

   private:
    /** The extrinsics on /tf_static, once, at the first observation's time. */
    void calibrationOnce(std::int64_t t_ns)
    {
        if (calibration_written_ || !sink_->carriesCalibration()) return;
        calibration_written_ = true;
        sink_->tfStatic(kTfStaticTopic, {transformOf(calib_.rig.T_body_left, kBodyFrame, "cam0", t_ns),
                                         transformOf(calib_.rig.T_left_right, "cam0", "cam1", t_ns)});
    }

    void image(const std::string& topic, const char* frame, std::int64_t t_ns, const cv::Mat& gray)
    {
        if (o_.image_encoding == BagImageEncoding::Mono8 || o_.image_encoding == BagImageEncoding::Mono16)
        {
            ImageMsg msg = imageMsgFromGray(gray, o_.image_encoding == BagImageEncoding::Mono16);
            msg.header = {t_ns, frame};
            sink_->image(topic, msg);
        }
        else
        {
            CompressedImageMsg msg =
                compressedMsgFromGray(gray, o_.image_encoding == BagImageEncoding::Png, o_.jpeg_quality);
            msg.header = {t_ns, frame};
            sink_->compressedImage(topic, msg);
        }
    }

    const Rawlog2BagOptions& o_;
    const dataset::SensorCalibration& calib_;
    std::unique_ptr<BagSink> sink_;
    bool calibration_written_ = false;
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
    const bool mcap = o.format == dataset::BagFormat::Mcap;
    require(mcap || haveRos1(), o.output_bag + " ([Rawlog2Bag] format)",
            "ros1: this build writes no ROS 1 bags (install librosbag-dev and rebuild), use format=mcap");
    const std::string tmp_bag = mcap ? staged.addFolder(o.output_bag) : staged.addFile(o.output_bag);
    core::writeTextFileAtomically(
        staged.addFile(o.camchainPath()),
        "# Kalibr camchain written by rawlog2bag from " + o.calibration_ini + "\n" +
            dataset::kalibrCamchainText(calib.rig, o.left_topic, o.right_topic, o.calibration_ini));
    core::writeTextFileAtomically(staged.addFile(o.imuYamlPath()),
                                  "# Kalibr IMU noise model written by rawlog2bag from " + o.calibration_ini + "\n" +
                                      dataset::kalibrImuText(imu, o.imu_topic));

    BagWriter bag(o, calib,
                  mcap ? makeMcapBagSink(tmp_bag, fs::path(o.output_bag).filename().string(), o.compression)
                       : makeRos1BagSink(tmp_bag, o.compression));
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
                 i && i->has(IMU_X_ACC) && i->has(IMU_Y_ACC) && i->has(IMU_Z_ACC) && i->has(IMU_WX) && i->has(IMU_WY) &&
                 i->has(IMU_WZ))
            bag.imu(t_ns, *i);
        else
            ++bag.r.ignored;
    };
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
    progressLine(o.progress, total, total, bag.r, true, shown);
    staged.commit();
    Rawlog2BagResult r = bag.r;
    r.bag_path = o.output_bag;
    r.camchain_path = o.camchainPath();
    r.imu_yaml_path = o.imuYamlPath();
    r.bag_bytes = 0;
    if (fs::is_directory(o.output_bag))
        for (const auto& e : fs::directory_iterator(o.output_bag)) r.bag_bytes += e.file_size();
    else
        r.bag_bytes = fs::file_size(o.output_bag);
    return r;
}

}  // namespace quasiloc::ros
