#pragma once
// A ROS 1 or ROS 2 bag (message_source.h) -> the stereo + IMU rawlog quasiloc-track reads (+ <name>_Images/), the
// calibration INI and, with a ground-truth topic, a TUM file of T_world_cam0. The work of the program bag2rawlog, in
// the library so that tests can run it.
#include <mrpt/system/CTimeLogger.h>

#include <cstdint>
#include <quasiloc/dataset/bag_options.h>
#include <string>
#include <vector>

namespace quasiloc::ros
{
using dataset::Bag2RawlogOptions;
using dataset::GroundTruthFrame;

struct Bag2RawlogResult
{
    std::string rawlog_path, images_folder, calib_path, gt_path;
    std::uint64_t bag_bytes = 0;
    std::string bag_format;  ///< "ROS 1 bag", "rosbag2 mcap", ...
    std::size_t left_msgs = 0, right_msgs = 0, imu_msgs = 0, gt_msgs = 0;
    std::size_t stereo_written = 0, imu_written = 0, gt_written = 0;
    std::size_t unpaired_left = 0, unpaired_right = 0, out_of_order = 0, late_dropped = 0;
    std::vector<std::string> unpaired_report;  ///< the first unpaired images, one line each
    double max_pair_offset_ms = 0;             ///< the largest |t_right - t_left| of a written pair
    std::int64_t first_frame_ns = 0, last_frame_ns = 0;
    std::string left_type, right_type;  ///< message types of the two image topics
};

/** Converts, streaming the bag. The rawlog, its images, the calibration and the ground truth appear only when the
 *  whole bag was read; any error (a topic missing from the bag or of an unsupported type, an unsupported image
 *  encoding, an image of the wrong size, a truncated or corrupt bag, an unknown storage or compression, a CameraInfo
 *  of an unsupported distortion model, no stereo pair at all) is an InputError naming the file and the topic, and
 *  leaves nothing. */
Bag2RawlogResult convertBagToRawlog(const Bag2RawlogOptions& options, mrpt::system::CTimeLogger* timer = nullptr);

}  // namespace quasiloc::ros
