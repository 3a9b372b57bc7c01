#pragma once
// tf2_msgs/TFMessage in ROS 1 bags. Debian ships geometry_msgs but no ROS 1 tf2_msgs: the message is one field,
// geometry_msgs/TransformStamped[] transforms, so it is read as that array's serialisation and written through a
// message type declared here with tf2_msgs/TFMessage's name, MD5 sum and definition (the same bytes as tf2's).
#include <geometry_msgs/TransformStamped.h>

#include <cstdint>
#include <quasiloc/ros/messages.h>
#include <string>
#include <vector>

namespace quasiloc::ros::ros1
{
/** ROS 1's tf2_msgs/TFMessage (and tf/tfMessage, the same fields). */
struct TFMessage
{
    std::vector<geometry_msgs::TransformStamped> transforms;
};

/** The transforms of a serialised TFMessage; InputError naming `where` for bytes that do not decode. */
std::vector<TransformMsg> transformsFromRos1(const std::vector<std::uint8_t>& payload, const std::string& where);
TFMessage toRos1(const std::vector<TransformMsg>& transforms);

}  // namespace quasiloc::ros::ros1

namespace ros::message_traits
{
template <>
struct MD5Sum<quasiloc::ros::ros1::TFMessage>
{
    static const char* value() { return "94810edda583a504dfda3829e70d7eec"; }
    static const char* value(const quasiloc::ros::ros1::TFMessage&) { return value(); }
};
template <>
struct DataType<quasiloc::ros::ros1::TFMessage>
{
    static const char* value() { return "tf2_msgs/TFMessage"; }
    static const char* value(const quasiloc::ros::ros1::TFMessage&) { return value(); }
};
template <>
struct Definition<quasiloc::ros::ros1::TFMessage>
{
    static const char* value();
    static const char* value(const quasiloc::ros::ros1::TFMessage&) { return value(); }
};
}  // namespace ros::message_traits

namespace ros::serialization
{
template <>
struct Serializer<quasiloc::ros::ros1::TFMessage>
{
    template <typename Stream, typename T>
    inline static void allInOne(Stream& stream, T m)
    {
        stream.next(m.transforms);
    }
    ROS_DECLARE_ALLINONE_SERIALIZER
};
}  // namespace ros::serialization
