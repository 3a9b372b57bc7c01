#pragma once
// sensor_msgs/PointCloud2 of ROS 1 (Debian's sensor_msgs headers) <-> the plain struct of point_cloud2.h.
#include <sensor_msgs/PointCloud2.h>

#include <quasiloc/ros/point_cloud2.h>

namespace quasiloc::ros::ros1
{
/** Moves the point data out of `m`. */
PointCloud2Msg fromRos1(sensor_msgs::PointCloud2&& m);
sensor_msgs::PointCloud2 toRos1(const PointCloud2Msg& m, std::uint32_t seq = 0);
}  // namespace quasiloc::ros::ros1
