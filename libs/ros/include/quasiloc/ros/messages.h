#pragma once
// The ROS messages bag2rawlog and rawlog2bag use, as plain structs independent of ROS 1 (roscpp's generated types)
// and ROS 2 (CDR bytes): each bag format converts its messages to and from these, so the conversion logic is shared.
// Field names and meanings follow sensor_msgs, geometry_msgs, nav_msgs and tf2_msgs.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace quasiloc::ros
{
/** std_msgs/Header (the ROS 1 seq is not kept). */
struct MsgHeader
{
    std::int64_t stamp_ns = 0;  ///< 0 when the publisher left it unset
    std::string frame_id;
};

/** sensor_msgs/Image */
struct ImageMsg
{
    MsgHeader header;
    std::uint32_t height = 0, width = 0, step = 0;
    std::string encoding;
    bool is_bigendian = false;
    std::vector<std::uint8_t> data;
};

/** sensor_msgs/CompressedImage */
struct CompressedImageMsg
{
    MsgHeader header;
    std::string format;
    std::vector<std::uint8_t> data;
};

/** sensor_msgs/Imu */
struct ImuMsg
{
    MsgHeader header;
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
    std::array<double, 9> orientation_covariance{};
    Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  ///< rad/s
    std::array<double, 9> angular_velocity_covariance{};
    Eigen::Vector3d linear_acceleration = Eigen::Vector3d::Zero();  ///< m/s^2
    std::array<double, 9> linear_acceleration_covariance{};
};

/** sensor_msgs/CameraInfo (binning and region of interest are read but not kept). */
struct CameraInfoMsg
{
    MsgHeader header;
    std::uint32_t height = 0, width = 0;
    std::string distortion_model;  ///< "plumb_bob", "rational_polynomial", "equidistant", ...
    std::vector<double> d;
    std::array<double, 9> k{}, r{};
    std::array<double, 12> p{};
};

/** geometry_msgs/TransformStamped: the pose of child_frame_id in header.frame_id (T_parent_child). */
struct TransformMsg
{
    MsgHeader header;
    std::string child_frame_id;
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();
    Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
};

/** A stamped pose: geometry_msgs/PoseStamped, geometry_msgs/TransformStamped or nav_msgs/Odometry's pose (the
 *  pose of the body in header.frame_id). */
struct PoseMsg
{
    MsgHeader header;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

/** Message type names as ROS 1 spells them ("sensor_msgs/Image"); ROS 2's "sensor_msgs/msg/Image" is normalised
 *  to this. */
namespace types
{
constexpr const char* kImage = "sensor_msgs/Image";
constexpr const char* kCompressedImage = "sensor_msgs/CompressedImage";
constexpr const char* kImu = "sensor_msgs/Imu";
constexpr const char* kCameraInfo = "sensor_msgs/CameraInfo";
constexpr const char* kPoseStamped = "geometry_msgs/PoseStamped";
constexpr const char* kTransformStamped = "geometry_msgs/TransformStamped";
constexpr const char* kOdometry = "nav_msgs/Odometry";
constexpr const char* kTFMessage = "tf2_msgs/TFMessage";
}  // namespace types

/** "pkg/msg/Name" -> "pkg/Name"; anything else is returned unchanged. */
std::string normalisedTypeName(const std::string& type);

}  // namespace quasiloc::ros
