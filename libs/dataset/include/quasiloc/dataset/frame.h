#pragma once
// What every data source (MRPT rawlog, EuRoC ASL folder, simulator) yields to the estimator.
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

namespace quasiloc::dataset
{
/** One IMU reading in the body (IMU) frame: specific force [m/s^2] and angular rate [rad/s]. */
struct ImuSample
{
    double t = 0;  ///< seconds
    Eigen::Vector3d acc = Eigen::Vector3d::Zero();
    Eigen::Vector3d gyro = Eigen::Vector3d::Zero();
};

struct StereoFrame
{
    size_t index = 0;      ///< 0, 1, 2, ... in the order yielded
    double timestamp = 0;  ///< seconds (left image time)
    cv::Mat left, right;   ///< CV_8UC1, raw (not rectified) images
    /** IMU samples with previous frame's timestamp < t <= this frame's timestamp (for the first frame:
     *  all samples up to its timestamp). */
    std::vector<ImuSample> imu;
    std::optional<mrpt::poses::CPose3D> T_world_cam0;  ///< ground truth, when the source has it
};

}  // namespace quasiloc::dataset
