#pragma once
// map-build's scans and trajectory from a ROS 1 or ROS 2 bag (message_source.h opens either: a .bag through Debian's
// librosbag, a rosbag2 folder / .db3 / .mcap through our own SQLite3 and MCAP readers).
//  - BagScanSource: one scan per sensor_msgs/PointCloud2 message of a topic, in the bag's order, named
//    "<bag> topic <topic> message <i>" (i from 0) and stamped by the message header. The bag is read once when the
//    source opens (every message decoded and checked, so that a bad message stops map-build before its first pass),
//    then once per forEach (map-build's passes). lidarFrame() is the messages' header.frame_id (the LiDAR's frame
//    in /tf_static, static_transforms.h).
//  - readBagTrajectory: T_world_body from a geometry_msgs/PoseStamped, nav_msgs/Odometry (its pose) or
//    geometry_msgs/TransformStamped topic, at the header stamps, as map::ScanPoses interpolates a TUM file.
//  - readBagExtrinsic: T_body_lidar chained through the bag's static transforms (/tf_static).
// Stamps in seconds are the doubles nearest the exact decimal times (as a TUM or times file spelling the same
// nanoseconds is parsed), so that scans and poses from a bag meet the same poses as from files.
#include <cstdint>
#include <memory>
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/map/lidar_scan.h>
#include <quasiloc/ros/message_source.h>
#include <string>
#include <vector>

namespace quasiloc::ros
{
class BagScanSource : public map::ScanSource
{
   public:
    /** `topic` empty: the bag's only PointCloud2 topic. InputError naming the bag for a bag that does not open, a
     *  missing topic (the message lists the bag's PointCloud2 topics), a topic of another type or without messages;
     *  naming the message for one that does not decode or has no valid layout (scanFromPointCloud2). */
    BagScanSource(const std::string& bag, const std::string& topic);

    size_t size() const override { return stamps_ns_.size(); }
    std::string name(size_t i) const override;
    /** Reads the bag from its start up to message i: use forEach to read them all. */
    map::LidarScan read(size_t i) const override;
    void forEach(const std::function<void(size_t, map::LidarScan&&)>& visit) const override;

    const std::string& topic() const { return topic_; }
    /** e.g. "39 PointCloud2 messages of /velodyne_points in run.bag (ROS 1 bag)". */
    std::string describe() const;
    /** Each scan's header stamp in seconds; InputError naming the first message whose stamp is unset (0). */
    std::vector<double> stampsSeconds() const;
    std::int64_t stampNs(size_t i) const { return stamps_ns_.at(i); }
    /** The LiDAR's frame: the header.frame_id of every message. InputError naming the first message whose frame_id
     *  differs from message 0's, or message 0 when it is empty. */
    std::string lidarFrame() const;

   private:
    map::LidarScan decode(const BagMessage& m, size_t i) const;

    std::unique_ptr<MessageSource> bag_;
    std::string topic_;
    std::vector<std::int64_t> stamps_ns_;
    std::string frame_id_;            ///< message 0's header.frame_id
    size_t other_frame_message_ = 0;  ///< the first message of another frame_id (0: none)
    std::string other_frame_id_;
};

/** T_world_body of `topic` in `bag`. InputError naming the bag for a missing topic, one of another type or without
 *  messages, and naming the message for an unset stamp, a non-finite value or a quaternion off unit length by more
 *  than 1e-2 (the TUM reader's rule; quaternions are normalised). */
core::Trajectory readBagTrajectory(const std::string& bag, const std::string& topic);

/** The LiDAR's extrinsic from a bag's static transforms: T_body_lidar, and the frames chained ("base_link <- imu ->
 *  velodyne", static_transforms.h). */
struct BagExtrinsic
{
    Eigen::Isometry3d T_body_lidar = Eigen::Isometry3d::Identity();
    std::string chain;
};

/** The pose of `lidar_frame` (the header.frame_id of the scans of `lidar_topic`) in `body_frame`, chained through
 *  the TFMessages of `tf_topic` in `bag`. InputError naming the bag, tf_topic, both frames and lidar_topic for a
 *  missing topic, no transform, a frame in no transform, frames not connected, or a cycle; the message lists the
 *  transforms the topic does hold. */
BagExtrinsic readBagExtrinsic(const std::string& bag, const std::string& tf_topic, const std::string& body_frame,
                              const std::string& lidar_frame, const std::string& lidar_topic);

/** The double nearest ns / 1e9 (correctly rounded, as parsing the decimal time would give). */
double secondsFromNs(std::int64_t ns);

}  // namespace quasiloc::ros
