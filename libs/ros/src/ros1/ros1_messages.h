#pragma once
// ROS 1 message types (Debian's sensor_msgs, geometry_msgs, nav_msgs headers) <-> the plain structs of messages.h.
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>

#include <quasiloc/ros/messages.h>

namespace quasiloc::ros::ros1
{
MsgHeader fromRos1(const std_msgs::Header& h);
std_msgs::Header toRos1(const MsgHeader& h, std::uint32_t seq);

ImageMsg fromRos1(const sensor_msgs::Image& m);
CompressedImageMsg fromRos1(const sensor_msgs::CompressedImage& m);
ImuMsg fromRos1(const sensor_msgs::Imu& m);
CameraInfoMsg fromRos1(const sensor_msgs::CameraInfo& m);
PoseMsg fromRos1(const geometry_msgs::PoseStamped& m);
TransformMsg fromRos1(const geometry_msgs::TransformStamped& m);
PoseMsg fromRos1(const nav_msgs::Odometry& m);

sensor_msgs::Image toRos1(const ImageMsg& m, std::uint32_t seq = 0);
sensor_msgs::CompressedImage toRos1(const CompressedImageMsg& m, std::uint32_t seq = 0);
sensor_msgs::Imu toRos1(const ImuMsg& m, std::uint32_t seq = 0);
geometry_msgs::PoseStamped toRos1(const PoseMsg& m, std::uint32_t seq = 0);

}  // namespace quasiloc::ros::ros1
