#pragma once
// The ROS 2 message definitions (ros2msg text: the type's fields, then each type it uses after a line of '='
// and "MSG: <type>") that rawlog2bag stores as MCAP schemas, so that tools which decode by schema (Foxglove, the
// mcap CLI) read our bags without a ROS installation.
#include <string>

namespace quasiloc::ros
{
/** The definition of "sensor_msgs/msg/Image", ..., or an empty string for a type it does not know. */
std::string ros2MessageDefinition(const std::string& type);
}  // namespace quasiloc::ros
