// ROS 2 message definitions for MCAP schemas (ros2_msg_definitions.h), as the .msg files of sensor_msgs,
// geometry_msgs, std_msgs, builtin_interfaces and tf2_msgs declare the fields (comments and constants left out).
#include <map>
#include <vector>

#include "ros2_msg_definitions.h"

namespace quasiloc::ros
{
namespace
{
const std::map<std::string, std::string>& definitions()
{
    static const std::map<std::string, std::string> d = {
        {"builtin_interfaces/Time", "int32 sec\nuint32 nanosec\n"},
        {"std_msgs/Header", "builtin_interfaces/Time stamp\nstring frame_id\n"},
        {"geometry_msgs/Vector3", "float64 x\nfloat64 y\nfloat64 z\n"},
        {"geometry_msgs/Point", "float64 x\nfloat64 y\nfloat64 z\n"},
        {"geometry_msgs/Quaternion", "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n"},
        {"geometry_msgs/Pose", "Point position\nQuaternion orientation\n"},
        {"geometry_msgs/Transform", "Vector3 translation\nQuaternion rotation\n"},
        {"geometry_msgs/TransformStamped", "std_msgs/Header header\nstring child_frame_id\nTransform transform\n"},
        {"geometry_msgs/PoseStamped", "std_msgs/Header header\nPose pose\n"},
        {"sensor_msgs/RegionOfInterest",
         "uint32 x_offset\nuint32 y_offset\nuint32 height\nuint32 width\nbool do_rectify\n"},
        {"sensor_msgs/Image",
         "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\nuint32 step\n"
         "uint8[] data\n"},
        {"sensor_msgs/CompressedImage", "std_msgs/Header header\nstring format\nuint8[] data\n"},
        {"sensor_msgs/Imu",
         "std_msgs/Header header\ngeometry_msgs/Quaternion orientation\nfloat64[9] orientation_covariance\n"
         "geometry_msgs/Vector3 angular_velocity\nfloat64[9] angular_velocity_covariance\n"
         "geometry_msgs/Vector3 linear_acceleration\nfloat64[9] linear_acceleration_covariance\n"},
        {"sensor_msgs/CameraInfo",
         "std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\nfloat64[] d\nfloat64[9] k\n"
         "float64[9] r\nfloat64[12] p\nuint32 binning_x\nuint32 binning_y\nRegionOfInterest roi\n"},
        {"tf2_msgs/TFMessage", "geometry_msgs/TransformStamped[] transforms\n"},
        {"sensor_msgs/PointField", "string name\nuint32 offset\nuint8 datatype\nuint32 count\n"},
        {"sensor_msgs/PointCloud2",
         "std_msgs/Header header\nuint32 height\nuint32 width\nPointField[] fields\nbool is_bigendian\n"
         "uint32 point_step\nuint32 row_step\nuint8[] data\nbool is_dense\n"},
    };
    return d;
}

/** The types a definition uses, in the order they are appended. */
const std::map<std::string, std::vector<std::string>>& dependencies()
{
    static const std::map<std::string, std::vector<std::string>> d = {
        {"sensor_msgs/Image", {"std_msgs/Header", "builtin_interfaces/Time"}},
        {"sensor_msgs/CompressedImage", {"std_msgs/Header", "builtin_interfaces/Time"}},
        {"sensor_msgs/Imu",
         {"std_msgs/Header", "builtin_interfaces/Time", "geometry_msgs/Quaternion", "geometry_msgs/Vector3"}},
        {"sensor_msgs/CameraInfo", {"std_msgs/Header", "builtin_interfaces/Time", "sensor_msgs/RegionOfInterest"}},
        {"geometry_msgs/PoseStamped",
         {"std_msgs/Header", "builtin_interfaces/Time", "geometry_msgs/Pose", "geometry_msgs/Point",
          "geometry_msgs/Quaternion"}},
        {"sensor_msgs/PointCloud2", {"std_msgs/Header", "builtin_interfaces/Time", "sensor_msgs/PointField"}},
        {"tf2_msgs/TFMessage",
         {"geometry_msgs/TransformStamped", "std_msgs/Header", "builtin_interfaces/Time", "geometry_msgs/Transform",
          "geometry_msgs/Vector3", "geometry_msgs/Quaternion"}},
    };
    return d;
}
}  // namespace

std::string ros2MessageDefinition(const std::string& type)
{
    // "sensor_msgs/msg/Image" -> "sensor_msgs/Image"
    std::string key = type;
    if (const auto p = key.find("/msg/"); p != std::string::npos) key.erase(p, 4);
    const auto it = definitions().find(key);
    if (it == definitions().end()) return {};
    std::string text = it->second;
    if (const auto deps = dependencies().find(key); deps != dependencies().end())
        for (const auto& dep : deps->second)
            text += std::string(80, '=') + "\nMSG: " + dep + "\n" + definitions().at(dep);
    return text;
}

}  // namespace quasiloc::ros
