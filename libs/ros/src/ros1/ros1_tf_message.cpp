// tf2_msgs/TFMessage in ROS 1 bags (ros1_tf_message.h).
#include "ros1_tf_message.h"

#include <quasiloc/core/error.h>

#include "ros1_messages.h"

namespace ros::message_traits
{
const char* Definition<quasiloc::ros::ros1::TFMessage>::value()
{
    static const std::string definition =
        std::string(
            "geometry_msgs/TransformStamped[] transforms\n\n"
            "================================================================================\n"
            "MSG: geometry_msgs/TransformStamped\n") +
        Definition<geometry_msgs::TransformStamped>::value();
    return definition.c_str();
}
}  // namespace ros::message_traits

namespace quasiloc::ros::ros1
{
std::vector<TransformMsg> transformsFromRos1(const std::vector<std::uint8_t>& payload, const std::string& where)
{
    std::vector<geometry_msgs::TransformStamped> transforms;
    try
    {
        std::vector<std::uint8_t> bytes = payload;
        ::ros::serialization::IStream stream(bytes.data(), std::uint32_t(bytes.size()));
        ::ros::serialization::deserialize(stream, transforms);
    }
    catch (const ::ros::Exception& e)
    {
        throw core::InputError(where, std::string("cannot read the TFMessage: ") + e.what());
    }
    std::vector<TransformMsg> r;
    for (const auto& t : transforms) r.push_back(fromRos1(t));
    return r;
}

TFMessage toRos1(const std::vector<TransformMsg>& transforms)
{
    TFMessage m;
    for (const TransformMsg& t : transforms)
    {
        geometry_msgs::TransformStamped r;
        r.header = toRos1(t.header, 0);
        r.child_frame_id = t.child_frame_id;
        r.transform.translation.x = t.translation.x();
        r.transform.translation.y = t.translation.y();
        r.transform.translation.z = t.translation.z();
        r.transform.rotation.x = t.rotation.x();
        r.transform.rotation.y = t.rotation.y();
        r.transform.rotation.z = t.rotation.z();
        r.transform.rotation.w = t.rotation.w();
        m.transforms.push_back(r);
    }
    return m;
}

}  // namespace quasiloc::ros::ros1
