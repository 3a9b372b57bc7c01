// openMessageSource (message_source.h): a ROS 1 bag or a ROS 2 bag, by what the path is.
#include <filesystem>
#include <fstream>
#include <quasiloc/core/error.h>
#include <quasiloc/ros/message_source.h>
#include <quasiloc/ros/rosbag2_source.h>

#include "bag_sink.h"
#ifdef QUASILOC_HAVE_ROS1
#include "ros1/ros1_source.h"
#endif

namespace fs = std::filesystem;

namespace quasiloc::ros
{
std::string BagMessage::where() const
{
    return file() + " topic " + topic() + " (message at t=" + std::to_string(timeNs()) + " ns)";
}

bool haveRos1()
{
#ifdef QUASILOC_HAVE_ROS1
    return true;
#else
    return false;
#endif
}

std::unique_ptr<MessageSource> openMessageSource(const std::string& path)
{
    std::error_code ec;
    bool ros1 = false;
    if (fs::is_regular_file(path, ec))
    {
        char head[13] = {};
        std::ifstream(path, std::ios::binary).read(head, sizeof head);
        ros1 = std::string(head, 13) == "#ROSBAG V2.0\n" || fs::path(path).extension() == ".bag";
    }
    if (!ros1) return openRosbag2(path);
#ifdef QUASILOC_HAVE_ROS1
    return openRos1Bag(path);
#else
    throw core::InputError(path, "a ROS 1 bag, and this build reads none (install librosbag-dev and rebuild)");
#endif
}

#ifndef QUASILOC_HAVE_ROS1
std::unique_ptr<BagSink> makeRos1BagSink(const std::string& path, dataset::BagCompression)
{
    throw core::InputError(path, "this build writes no ROS 1 bags (install librosbag-dev and rebuild)");
}
#endif

}  // namespace quasiloc::ros
