#pragma once
// Writing a bag of LiDAR scans, poses and static transforms: a ROS 1 bag file, or a rosbag2 folder with one MCAP file
// and its metadata.yaml (rawlog2bag's writers, bag_sink.h). The tests of map-build's bag source write their bags with
// it (tests/map_build_bag).
#include <memory>
#include <quasiloc/dataset/bag_options.h>
#include <quasiloc/ros/messages.h>
#include <quasiloc/ros/point_cloud2.h>
#include <string>
#include <vector>

namespace quasiloc::ros
{
class BagSink;

class BagWriter
{
   public:
    /** A ROS 1 bag at `path`, or a rosbag2 folder `path` (created; <folder name>_0.mcap inside). InputError naming
     *  the path when it cannot be written or this build has no ROS 1 bags. */
    BagWriter(const std::string& path, dataset::BagFormat format,
              dataset::BagCompression compression = dataset::BagCompression::None);
    ~BagWriter();
    /** Messages of a topic come in time order; each is stamped (bag time, MCAP log time) by its header. */
    void pointCloud2(const std::string& topic, const PointCloud2Msg& m);
    /** As geometry_msgs/PoseStamped. */
    void pose(const std::string& topic, const PoseMsg& m);
    /** As one tf2_msgs/TFMessage (a static transforms topic such as /tf_static), stamped by its first transform. */
    void tfStatic(const std::string& topic, const std::vector<TransformMsg>& transforms);
    /** Completes the bag (index, summary, metadata). */
    void close();

   private:
    std::unique_ptr<BagSink> sink_;
};

}  // namespace quasiloc::ros
