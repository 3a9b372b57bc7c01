// ROS 1 message conversions (ros1_messages.h).
#include "ros1_messages.h"

namespace quasiloc::ros::ros1
{
namespace
{
Eigen::Vector3d vec(const geometry_msgs::Vector3& v) { return {v.x, v.y, v.z}; }
Eigen::Vector3d vec(const geometry_msgs::Point& v) { return {v.x, v.y, v.z}; }
Eigen::Quaterniond quat(const geometry_msgs::Quaternion& q) { return Eigen::Quaterniond(q.w, q.x, q.y, q.z); }
geometry_msgs::Quaternion quat(const Eigen::Quaterniond& q)
{
    geometry_msgs::Quaternion r;
    r.w = q.w();
    r.x = q.x();
    r.y = q.y();
    r.z = q.z();
    return r;
}
geometry_msgs::Vector3 vec3(const Eigen::Vector3d& v)
{
    geometry_msgs::Vector3 r;
    r.x = v.x();
    r.y = v.y();
    r.z = v.z();
    return r;
}
template <std::size_t N, typename B>
std::array<double, N> arr(const B& boost_array)
{
    std::array<double, N> a;
    std::copy(boost_array.begin(), boost_array.end(), a.begin());
    return a;
}
}  // namespace

MsgHeader fromRos1(const std_msgs::Header& h) { return {std::int64_t(h.stamp.toNSec()), h.frame_id}; }

std_msgs::Header toRos1(const MsgHeader& h, std::uint32_t seq)
{
    std_msgs::Header r;
    r.stamp.fromNSec(std::uint64_t(h.stamp_ns));
    r.frame_id = h.frame_id;
    r.seq = seq;
    return r;
}

ImageMsg fromRos1(const sensor_msgs::Image& m)
{
    return {fromRos1(m.header), m.height, m.width, m.step, m.encoding, m.is_bigendian != 0, m.data};
}

CompressedImageMsg fromRos1(const sensor_msgs::CompressedImage& m) { return {fromRos1(m.header), m.format, m.data}; }

ImuMsg fromRos1(const sensor_msgs::Imu& m)
{
    ImuMsg r;
    r.header = fromRos1(m.header);
    r.orientation = quat(m.orientation);
    r.orientation_covariance = arr<9>(m.orientation_covariance);
    r.angular_velocity = vec(m.angular_velocity);
    r.angular_velocity_covariance = arr<9>(m.angular_velocity_covariance);
    r.linear_acceleration = vec(m.linear_acceleration);
    r.linear_acceleration_covariance = arr<9>(m.linear_acceleration_covariance);
    return r;
}

CameraInfoMsg fromRos1(const sensor_msgs::CameraInfo& m)
{
    CameraInfoMsg r;
    r.header = fromRos1(m.header);
    r.height = m.height;
    r.width = m.width;
    r.distortion_model = m.distortion_model;
    r.d = m.D;
    r.k = arr<9>(m.K);
    r.r = arr<9>(m.R);
    r.p = arr<12>(m.P);
    return r;
}

PoseMsg fromRos1(const geometry_msgs::PoseStamped& m)
{
    return {fromRos1(m.header), vec(m.pose.position), quat(m.pose.orientation)};
}

TransformMsg fromRos1(const geometry_msgs::TransformStamped& m)
{
    return {fromRos1(m.header), m.child_frame_id, vec(m.transform.translation), quat(m.transform.rotation)};
}

PoseMsg fromRos1(const nav_msgs::Odometry& m)
{
    return {fromRos1(m.header), vec(m.pose.pose.position), quat(m.pose.pose.orientation)};
}

sensor_msgs::Image toRos1(const ImageMsg& m, std::uint32_t seq)
{
    sensor_msgs::Image r;
    r.header = toRos1(m.header, seq);
    r.height = m.height;
    r.width = m.width;
    r.step = m.step;
    r.encoding = m.encoding;
    r.is_bigendian = m.is_bigendian ? 1 : 0;
    r.data = m.data;
    return r;
}

sensor_msgs::CompressedImage toRos1(const CompressedImageMsg& m, std::uint32_t seq)
{
    sensor_msgs::CompressedImage r;
    r.header = toRos1(m.header, seq);
    r.format = m.format;
    r.data = m.data;
    return r;
}

sensor_msgs::Imu toRos1(const ImuMsg& m, std::uint32_t seq)
{
    sensor_msgs::Imu r;
    r.header = toRos1(m.header, seq);
    r.orientation = quat(m.orientation);
    std::copy(m.orientation_covariance.begin(), m.orientation_covariance.end(), r.orientation_covariance.begin());
    r.angular_velocity = vec3(m.angular_velocity);
    std::copy(m.angular_velocity_covariance.begin(), m.angular_velocity_covariance.end(),
              r.angular_velocity_covariance.begin());
    r.linear_acceleration = vec3(m.linear_acceleration);
    std::copy(m.linear_acceleration_covariance.begin(), m.linear_acceleration_covariance.end(),
              r.linear_acceleration_covariance.begin());
    return r;
}

geometry_msgs::PoseStamped toRos1(const PoseMsg& m, std::uint32_t seq)
{
    geometry_msgs::PoseStamped r;
    r.header = toRos1(m.header, seq);
    r.pose.position.x = m.position.x();
    r.pose.position.y = m.position.y();
    r.pose.position.z = m.position.z();
    r.pose.orientation = quat(m.orientation);
    return r;
}

}  // namespace quasiloc::ros::ros1
