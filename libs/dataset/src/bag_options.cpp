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
    t.add("input_bag", input_bag, "the ROS 1 bag to read (streamed, never loaded whole)");
    t.add("output", output, "the rawlog to write; images go to <name>_Images/ beside it");
    t.add("left_topic", left_topic, "left camera: sensor_msgs/Image or sensor_msgs/CompressedImage");
    t.add("right_topic", right_topic, "right camera: sensor_msgs/Image or sensor_msgs/CompressedImage");
    t.add("imu_topic", imu_topic, "sensor_msgs/Imu, in the body (IMU) frame of the calibration");
    t.add("groundtruth_topic", groundtruth_topic,
          "optional: geometry_msgs/PoseStamped, geometry_msgs/TransformStamped or nav_msgs/Odometry");
    t.addEnum("groundtruth_frame", groundtruth_frame,
              {{"body", GroundTruthFrame::Body}, {"cam0", GroundTruthFrame::Cam0}},
              "which frame the ground-truth poses are of: body (IMU; multiplied by T_body_left) or cam0");
    t.add("kalibr_camchain", kalibr_camchain, "Kalibr camchain YAML (cam0 = left, cam1 = right)");
    t.add("kalibr_imu", kalibr_imu, "Kalibr IMU YAML (noise densities and update_rate)");
    t.add("calibration_ini", calibration_ini,
          "instead of the two Kalibr files: a quasiloc calibration INI (docs/calibration.md)");
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
        require(!kalibr_camchain.empty(), key("Bag2Rawlog", "kalibr_camchain"),
                "is empty: give the Kalibr camchain YAML (or calibration_ini)");
        require(!kalibr_imu.empty(), key("Bag2Rawlog", "kalibr_imu"), "is empty: give the Kalibr IMU YAML (or calibration_ini)");
    }
    else
        require(kalibr_camchain.empty() && kalibr_imu.empty(), key("Bag2Rawlog", "calibration_ini"),
                "is given together with kalibr_camchain / kalibr_imu: give one or the other");
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
    t.add("output_bag", output_bag, "the ROS 1 bag to write");
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
              {{"none", BagCompression::None}, {"bz2", BagCompression::Bz2}, {"lz4", BagCompression::Lz4}},
              "chunk compression of the bag");
    t.add("right_delay_ms", right_delay_ms, "ms", Range::any(),
          "added to the right images' stamps: emulates cameras that are not triggered together (tests of pairing)");
    t.add("progress", progress, "print the progress on stderr");
}

void Rawlog2BagOptions::check() const
{
    checkRanges("Rawlog2Bag");
    require(!input_rawlog.empty(), key("Rawlog2Bag", "input_rawlog"), "is empty: give the rawlog to read");
    require(!calibration_ini.empty(), key("Rawlog2Bag", "calibration_ini"), "is empty: give the rawlog's calibration INI");
    require(!output_bag.empty(), key("Rawlog2Bag", "output_bag"), "is empty: give the bag to write");
    require(!fs::is_directory(output_bag), key("Rawlog2Bag", "output_bag"), "'" + output_bag + "' is a folder");
    require(left_topic != right_topic, key("Rawlog2Bag", "right_topic"), "is the same topic as left_topic");
}

std::string Rawlog2BagOptions::camchainPath() const { return besideFile(output_bag, "_camchain.yaml"); }
std::string Rawlog2BagOptions::imuYamlPath() const { return besideFile(output_bag, "_imu.yaml"); }

}  // namespace quasiloc::dataset
