// The options of bag2rawlog and rawlog2bag (bag_options.h).
#include <filesystem>
#include <quasiloc/core/error.h>
#include <quasiloc/dataset/bag_options.h>

namespace fs = std::filesystem;
using quasiloc::core::require;

namespace quasiloc::dataset
{
namespace
{
std::string key(const char* section, const std::string& k) { return std::string("[") + section + "] " + k; }

std::string besideFile(const std::string& path, const std::string& suffix)
{
    const fs::path p(path);
    return (p.parent_path() / (p.stem().string() + suffix)).string();
}
}  // namespace

void Bag2RawlogOptions::declare(core::OptionTable& t)
{
    using core::Range;
    t.add("input_bag", input_bag,
          "the bag to read (streamed): a ROS 1 .bag, a rosbag2 folder (metadata.yaml + .db3 or .mcap files), or one "
          ".db3 / .mcap file");
    t.add("output", output, "the rawlog to write; images go to <name>_Images/ beside it");
    t.add("left_topic", left_topic, "left camera: sensor_msgs/Image or sensor_msgs/CompressedImage");
    t.add("right_topic", right_topic, "right camera: sensor_msgs/Image or sensor_msgs/CompressedImage");
    t.add("imu_topic", imu_topic, "sensor_msgs/Imu, in the body (IMU) frame of the calibration");
    t.add("groundtruth_topic", groundtruth_topic,
          "optional: geometry_msgs/PoseStamped, geometry_msgs/TransformStamped or nav_msgs/Odometry");
    t.addEnum("groundtruth_frame", groundtruth_frame,
              {{"body", GroundTruthFrame::Body}, {"cam0", GroundTruthFrame::Cam0}},
              "which frame the ground-truth poses are of: body (IMU; multiplied by T_body_left) or cam0");
    t.add("kalibr_camchain", kalibr_camchain,
          "Kalibr camchain YAML (cam0 = left, cam1 = right); empty = the cameras from the bag's CameraInfo and "
          "static transforms");
    t.add("kalibr_imu", kalibr_imu, "Kalibr IMU YAML (noise densities and update_rate); or imu_ini");
    t.add("imu_ini", imu_ini,
          "instead of kalibr_imu: an INI file whose [imu] section is the noise model "
          "(docs/calibration.md keys)");
    t.add("calibration_ini", calibration_ini,
          "instead of the Kalibr files: a quasiloc calibration INI (docs/calibration.md)");
    t.add("left_camera_info_topic", left_camera_info_topic,
          "without kalibr_camchain: the left camera's sensor_msgs/CameraInfo (plumb_bob or equidistant); empty = "
          "<left_topic's namespace>/camera_info");
    t.add("right_camera_info_topic", right_camera_info_topic,
          "likewise for the right camera; empty = <right_topic's namespace>/camera_info");
    t.add("tf_static_topic", tf_static_topic,
          "without kalibr_camchain: tf2_msgs/TFMessage whose transforms link the IMU frame and both camera frames");
    t.add("imu_frame", imu_frame,
          "without kalibr_camchain: the IMU's tf frame (the body frame); empty = the IMU messages' frame_id");
    t.add("pair_tolerance_ms", pair_tolerance_ms, "ms", Range::atLeast(0),
          "a left and a right image pair when their header stamps differ by at most this");
    t.add("reorder_window_s", reorder_window_s, "s", Range::atLeast(0),
          "observations wait this long (in header time) to be written in time order; later ones are dropped");
    t.add("mono16_shift_bits", mono16_shift_bits, "bits", Range::between(0, 8),
          "mono16 images become 8-bit by this right shift (8 for full 16-bit, 4 for 12-bit data)");
    t.add("max_frames", max_frames, "", Range::atLeast(0), "0 = every stereo pair; N = the first N pairs");
    t.add("calib_out", calib_out, "calibration INI; empty = <output dir>/<name>_calib.ini");
    t.add("gt_out", gt_out, "ground truth TUM of T_world_cam0; empty = <output dir>/<name>_gt_cam0.tum");
    t.add("stereo_sensor_label", stereo_sensor_label, "sensorLabel of the stereo observations");
    t.add("imu_sensor_label", imu_sensor_label, "sensorLabel of the IMU observations");
    t.add("gz_compression_level", gz_compression_level, "", Range::between(0, 9), "gzip level of the rawlog");
    t.add("progress", progress, "print a progress bar on stderr");
}

void Bag2RawlogOptions::check() const
{
    checkRanges("Bag2Rawlog");
    require(!input_bag.empty(), key("Bag2Rawlog", "input_bag"), "is empty: give the ROS 1 bag to read");
    require(!output.empty(), key("Bag2Rawlog", "output"), "is empty: give the rawlog to write");
    require(!fs::is_directory(output), key("Bag2Rawlog", "output"), "'" + output + "' is a folder");
    for (const auto& [k, v] : {std::pair<std::string, std::string>{"left_topic", left_topic},
                               {"right_topic", right_topic},
                               {"imu_topic", imu_topic}})
        require(!v.empty(), key("Bag2Rawlog", k), "is empty");
    require(left_topic != right_topic, key("Bag2Rawlog", "right_topic"), "is the same topic as left_topic");
    if (calibration_ini.empty())
    {
        require(!kalibr_imu.empty() || !imu_ini.empty(), key("Bag2Rawlog", "kalibr_imu"),
                "is empty: give the IMU noise model, a Kalibr IMU YAML (or imu_ini, or calibration_ini)");
        require(kalibr_imu.empty() || imu_ini.empty(), key("Bag2Rawlog", "imu_ini"),
                "is given together with kalibr_imu: give one or the other");
    }
    else
        require(kalibr_camchain.empty() && kalibr_imu.empty() && imu_ini.empty(), key("Bag2Rawlog", "calibration_ini"),
                "is given together with kalibr_camchain / kalibr_imu / imu_ini: give one or the other");
}

namespace
{
std::string cameraInfoBeside(const std::string& image_topic)
{
    const auto slash = image_topic.find_last_of('/');
    return (slash == std::string::npos ? std::string() : image_topic.substr(0, slash)) + "/camera_info";
}
}  // namespace

std::string Bag2RawlogOptions::leftCameraInfoTopic() const
{
    return left_camera_info_topic.empty() ? cameraInfoBeside(left_topic) : left_camera_info_topic;
}

std::string Bag2RawlogOptions::rightCameraInfoTopic() const
{
    return right_camera_info_topic.empty() ? cameraInfoBeside(right_topic) : right_camera_info_topic;
}

std::string Bag2RawlogOptions::calibOutPath() const
{
    return calib_out.empty() ? besideFile(output, "_calib.ini") : calib_out;
}

std::string Bag2RawlogOptions::gtOutPath() const
{
    return gt_out.empty() ? besideFile(output, "_gt_cam0.tum") : gt_out;
}

void Rawlog2BagOptions::declare(core::OptionTable& t)
{
    using core::Range;
    t.add("input_rawlog", input_rawlog, "the stereo + IMU rawlog to read (images in <name>_Images/ beside it)");
    t.add("calibration_ini", calibration_ini, "its calibration INI; written beside the bag as Kalibr YAML files");
    t.add("groundtruth", groundtruth, "optional: TUM file of T_world_cam0, written as PoseStamped of the body frame");
    t.add("output_bag", output_bag,
          "the bag to write: a ROS 1 .bag file, or with format=mcap a rosbag2 folder (metadata.yaml + <name>_0.mcap)");
    t.addEnum(
        "format", format, {{"ros1", BagFormat::Ros1}, {"mcap", BagFormat::Mcap}},
        "ros1 (rosbag) or mcap (ROS 2: CDR messages, also CameraInfo per image and the extrinsics on /tf_static)");
    t.add("left_topic", left_topic, "topic of the left images");
    t.add("right_topic", right_topic, "topic of the right images");
    t.add("imu_topic", imu_topic, "topic of the IMU (sensor_msgs/Imu)");
    t.add("groundtruth_topic", groundtruth_topic, "topic of the ground truth (geometry_msgs/PoseStamped)");
    t.addEnum("image_encoding", image_encoding,
              {{"mono8", BagImageEncoding::Mono8},
               {"mono16", BagImageEncoding::Mono16},
               {"png", BagImageEncoding::Png},
               {"jpeg", BagImageEncoding::Jpeg}},
              "sensor_msgs/Image mono8 or mono16 (x 256), or sensor_msgs/CompressedImage png (lossless) or jpeg");
    t.add("jpeg_quality", jpeg_quality, "", Range::between(1, 100), "quality of jpeg images");
    t.addEnum("compression", compression,
              {{"none", BagCompression::None},
               {"bz2", BagCompression::Bz2},
               {"lz4", BagCompression::Lz4},
               {"zstd", BagCompression::Zstd}},
              "chunk compression of the bag: ros1 none, bz2 or lz4; mcap none, zstd or lz4");
    t.add("right_delay_ms", right_delay_ms, "ms", Range::any(),
          "added to the right images' stamps: emulates cameras that are not triggered together (tests of pairing)");
    t.add("progress", progress, "print the progress on stderr");
}

void Rawlog2BagOptions::check() const
{
    checkRanges("Rawlog2Bag");
    require(!input_rawlog.empty(), key("Rawlog2Bag", "input_rawlog"), "is empty: give the rawlog to read");
    require(!calibration_ini.empty(), key("Rawlog2Bag", "calibration_ini"),
            "is empty: give the rawlog's calibration INI");
    require(!output_bag.empty(), key("Rawlog2Bag", "output_bag"), "is empty: give the bag to write");
    if (format == BagFormat::Ros1)
        require(!fs::is_directory(output_bag), key("Rawlog2Bag", "output_bag"), "'" + output_bag + "' is a folder");
    else
        require(!fs::is_regular_file(output_bag), key("Rawlog2Bag", "output_bag"),
                "'" + output_bag + "' is a file (format=mcap writes a rosbag2 folder)");
    require(left_topic != right_topic, key("Rawlog2Bag", "right_topic"), "is the same topic as left_topic");
    require(format == BagFormat::Mcap || compression != BagCompression::Zstd, key("Rawlog2Bag", "compression"),
            "zstd is for format=mcap (a ROS 1 bag: none, bz2 or lz4)");
    require(format == BagFormat::Ros1 || compression != BagCompression::Bz2, key("Rawlog2Bag", "compression"),
            "bz2 is for format=ros1 (MCAP: none, zstd or lz4)");
}

std::string Rawlog2BagOptions::leftCameraInfoTopic() const { return cameraInfoBeside(left_topic); }
std::string Rawlog2BagOptions::rightCameraInfoTopic() const { return cameraInfoBeside(right_topic); }
std::string Rawlog2BagOptions::camchainPath() const { return besideFile(output_bag, "_camchain.yaml"); }
std::string Rawlog2BagOptions::imuYamlPath() const { return besideFile(output_bag, "_imu.yaml"); }

}  // namespace quasiloc::dataset
