#pragma once
// A ROS 1 bag as a MessageSource, through Debian's rosbag library (streamed by rosbag::View in time order).
#include <memory>
#include <quasiloc/ros/message_source.h>

namespace quasiloc::ros
{
std::unique_ptr<MessageSource> openRos1Bag(const std::string& path);
}
