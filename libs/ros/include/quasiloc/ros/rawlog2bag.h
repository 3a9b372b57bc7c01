#pragma once
// A stereo + IMU rawlog (the simulator's, or one bag2rawlog wrote) -> a ROS 1 bag or a ROS 2 bag (rosbag2 folder with
// one MCAP file; it also carries CameraInfo and the extrinsics on /tf_static), with the calibration as Kalibr
// camchain and IMU YAML files beside it: so that our simulated data can be looked at in ROS tools and so that the
// bag2rawlog round trip can be tested. The work of the program rawlog2bag.
#include <cstdint>
#include <quasiloc/dataset/bag_options.h>
#include <string>

namespace quasiloc::ros
{
using dataset::BagCompression;
using dataset::BagImageEncoding;
using dataset::Rawlog2BagOptions;

struct Rawlog2BagResult
{
    std::string bag_path, camchain_path, imu_yaml_path;
    std::size_t stereo_written = 0, imu_written = 0, gt_written = 0, ignored = 0;
    std::uint64_t bag_bytes = 0;
};

/** Converts, streaming the rawlog. The bag and the two YAML files appear only when complete; a missing image, an
 *  image that is not 8-bit gray of the calibration's size, or a corrupt rawlog is an InputError naming it. */
Rawlog2BagResult convertRawlogToBag(const Rawlog2BagOptions& options);

}  // namespace quasiloc::ros
