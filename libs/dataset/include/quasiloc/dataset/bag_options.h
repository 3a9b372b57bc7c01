#pragma once
// The options of the bag converters bag2rawlog and rawlog2bag (libs/ros; ROS 1 bags and ROS 2 rosbag2 bags): plain
// data, here so that the options reference (quasiloc-options) lists them whether or not the ROS bag library is
// installed.
#include <quasiloc/core/declared_options.h>
#include <string>

namespace quasiloc::dataset
{
enum class GroundTruthFrame
{
    Body,  ///< the poses are of the body (IMU) frame: multiplied by the rig's T_body_left
    Cam0   ///< the poses are of the left camera already
};

/** How images are stored in a bag that we write. */
enum class BagImageEncoding
{
    Mono8,   ///< sensor_msgs/Image, "mono8"
    Mono16,  ///< sensor_msgs/Image, "mono16", the 8-bit value times 256
    Png,     ///< sensor_msgs/CompressedImage, "mono8; png compressed" (lossless)
    Jpeg     ///< sensor_msgs/CompressedImage, "mono8; jpeg compressed" (lossy)
};

enum class BagCompression
{
    None,
    Bz2,  ///< ROS 1 only
    Lz4,  ///< ROS 1 chunks, or MCAP chunks (LZ4 frames)
    Zstd  ///< MCAP only
};

/** The bag rawlog2bag writes. */
enum class BagFormat
{
    Ros1,  ///< a ROS 1 bag file
    Mcap   ///< a rosbag2 folder: metadata.yaml + one MCAP file (ROS 2, CDR messages)
};

/** INI section [Bag2Rawlog]; each key's unit, range and meaning: declare() (bag_options.cpp). */
struct Bag2RawlogOptions : public core::DeclaredOptions
{
    std::string input_bag;
    std::string output;
    std::string left_topic = "/cam0/image_raw";
    std::string right_topic = "/cam1/image_raw";
    std::string imu_topic = "/imu0";
    std::string groundtruth_topic;
    GroundTruthFrame groundtruth_frame = GroundTruthFrame::Body;
    std::string kalibr_camchain;
    std::string kalibr_imu;
    std::string imu_ini;
    std::string calibration_ini;
    std::string left_camera_info_topic;
    std::string right_camera_info_topic;
    std::string tf_static_topic = "/tf_static";
    std::string imu_frame;
    double pair_tolerance_ms = 2.0;
    double reorder_window_s = 0.5;
    int mono16_shift_bits = 8;
    int max_frames = 0;
    std::string calib_out;
    std::string gt_out;
    std::string stereo_sensor_label = "stereo";
    std::string imu_sensor_label = "imu";
    int gz_compression_level = 1;
    bool progress = true;

    void declare(core::OptionTable& t) override;
    /** The declared ranges, then InputError naming "[Bag2Rawlog] <key>" for a missing input or a missing
     *  calibration (kalibr_camchain + kalibr_imu, or calibration_ini). */
    void check() const;

    /** Without a Kalibr camchain or calibration INI the cameras come from the bag (CameraInfo, /tf_static). */
    bool calibrationFromBag() const { return calibration_ini.empty() && kalibr_camchain.empty(); }
    std::string leftCameraInfoTopic() const;   ///< left_camera_info_topic or <left_topic's namespace>/camera_info
    std::string rightCameraInfoTopic() const;  ///< likewise for the right camera
    std::string calibOutPath() const;          ///< calib_out or <output stem>_calib.ini
    std::string gtOutPath() const;             ///< gt_out or <output stem>_gt_cam0.tum
};

/** INI section [Rawlog2Bag]; each key's unit, range and meaning: declare() (bag_options.cpp). */
struct Rawlog2BagOptions : public core::DeclaredOptions
{
    std::string input_rawlog;
    std::string calibration_ini;
    std::string groundtruth;
    std::string output_bag;
    std::string left_topic = "/cam0/image_raw";
    std::string right_topic = "/cam1/image_raw";
    std::string imu_topic = "/imu0";
    std::string groundtruth_topic = "/groundtruth";
    BagImageEncoding image_encoding = BagImageEncoding::Mono8;
    int jpeg_quality = 95;
    BagFormat format = BagFormat::Ros1;
    BagCompression compression = BagCompression::None;
    double right_delay_ms = 0;
    bool progress = true;

    void declare(core::OptionTable& t) override;
    void check() const;

    std::string leftCameraInfoTopic() const;   ///< format=mcap: <left_topic's namespace>/camera_info
    std::string rightCameraInfoTopic() const;  ///< format=mcap: <right_topic's namespace>/camera_info
    std::string camchainPath() const;          ///< <bag stem>_camchain.yaml beside the bag
    std::string imuYamlPath() const;           ///< <bag stem>_imu.yaml beside the bag
};

}  // namespace quasiloc::dataset
