#pragma once
// The static transforms of a bag (tf2_msgs/TFMessage on /tf_static, ROS 1 or ROS 2) as tf2 keeps them: a tree in
// which each frame has one parent (a frame given again takes its latest parent and transform, as tf2 does), and the
// transform between two frames is chained through their common ancestor, whichever direction each link was given
// in. bag2rawlog takes the cameras' extrinsics from it (bag_calibration.h), map-build the LiDAR's (T_body_lidar).
#include <map>
#include <mrpt/poses/CPose3D.h>
#include <optional>
#include <quasiloc/ros/message_source.h>
#include <quasiloc/ros/messages.h>
#include <string>
#include <utility>
#include <vector>

namespace quasiloc::ros
{
class StaticTransforms
{
   public:
    /** T_parent_child of a TransformStamped (its rotation normalised). */
    void add(const TransformMsg& t);
    /** T_from_to (the pose of frame `to` in frame `from`) through any chain of transforms, or nothing when the
     *  two frames are not connected or a cycle lies on the way. */
    std::optional<mrpt::poses::CPose3D> lookup(const std::string& from, const std::string& to) const;
    /** T_from_to as lookup(); InputError naming `where` when a frame is not in the tree, the frames are not
     *  connected, or the parents of a frame lead back to it (a cycle); the message lists the transforms there. */
    mrpt::poses::CPose3D chain(const std::string& from, const std::string& to, const std::string& where) const;
    /** The chain lookup follows, e.g. "base_link -> imu_link <- velodyne" (arrows parent -> child). */
    std::string describeChain(const std::string& from, const std::string& to) const;
    /** "a -> b, b -> c" for error messages (each frame's latest parent). */
    std::string describe() const;
    bool empty() const { return parent_.empty(); }
    bool hasFrame(const std::string& frame) const;

   private:
    struct Up
    {
        std::vector<std::pair<std::string, mrpt::poses::CPose3D>> path;  ///< (frame, T_frame_start), start first
        bool cycle = false;
    };
    /** The frames from `frame` up to its root, each with the pose of `frame` in it. */
    Up up(const std::string& frame) const;

    std::map<std::string, std::pair<std::string, mrpt::poses::CPose3D>> parent_;  ///< child -> (parent, T_p_c)
    std::vector<std::string> children_;  ///< in the order first given, for describe()
};

/** Every TFMessage of `topic` in `bag`. InputError naming the bag when the topic is missing (the message lists the
 *  bag's TFMessage topics), holds another type, or holds no transform; naming the message for one that does not
 *  decode. */
StaticTransforms readStaticTransforms(MessageSource& bag, const std::string& topic);

}  // namespace quasiloc::ros
