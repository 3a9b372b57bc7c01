// Scans and poses from a bag for map-build (bag_scan_source.h).
#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/ros/bag_scan_source.h>
#include <quasiloc/ros/static_transforms.h>

using quasiloc::core::InputError;

namespace quasiloc::ros
{
namespace
{
std::string topicsOfType(const MessageSource& bag, const std::vector<std::string>& types)
{
    std::string list;
    for (const auto& [topic, type] : bag.topicTypes())
        if (std::find(types.begin(), types.end(), type) != types.end()) list += (list.empty() ? "" : ", ") + topic;
    return list.empty() ? "none" : list;
}

/** Checks that `topic` is in the bag with one of `types`. */
void requireTopic(const MessageSource& bag, const std::string& topic, const std::vector<std::string>& types)
{
    std::string names;
    for (const std::string& t : types) names += (names.empty() ? "" : " or ") + t;
    const auto it = bag.topicTypes().find(topic);
    core::require(it != bag.topicTypes().end(), bag.path(),
                  "has no topic " + topic + " (its " + names + " topics: " + topicsOfType(bag, types) + ")");
    core::require(std::find(types.begin(), types.end(), it->second) != types.end(), bag.path(),
                  "topic " + topic + " holds " + it->second + " messages, not " + names);
}

/** Runs `decode` with InputErrors renamed to `name` (the bag readers name a message by its time, not its index). */
template <class F>
auto renamedErrors(const std::string& name, F&& decode)
{
    try
    {
        return decode();
    }
    catch (const InputError& e)
    {
        throw InputError(name, e.problem());
    }
}
}  // namespace

double secondsFromNs(std::int64_t ns)
{
    // The decimal spelling, parsed: strtod rounds correctly, double(ns) * 1e-9 does not.
    const bool negative = ns < 0;
    const std::uint64_t a = negative ? std::uint64_t(0) - std::uint64_t(ns) : std::uint64_t(ns);
    char text[48];
    std::snprintf(text, sizeof text, "%s%" PRIu64 ".%09" PRIu64, negative ? "-" : "", a / 1000000000u, a % 1000000000u);
    return std::strtod(text, nullptr);
}

BagScanSource::BagScanSource(const std::string& bag, const std::string& topic)
    : bag_(openMessageSource(bag)), topic_(topic)
{
    if (topic_.empty())
    {
        std::vector<std::string> clouds;
        for (const auto& [t, type] : bag_->topicTypes())
            if (type == types::kPointCloud2) clouds.push_back(t);
        core::require(!clouds.empty(), bag, "holds no sensor_msgs/PointCloud2 topic (set bag_lidar_topic)");
        core::require(clouds.size() == 1, bag,
                      "holds several PointCloud2 topics (" + topicsOfType(*bag_, {types::kPointCloud2}) +
                          "): set bag_lidar_topic");
        topic_ = clouds.front();
    }
    requireTopic(*bag_, topic_, {types::kPointCloud2});
    bag_->read({topic_}, [&](const BagMessage& m) {
        const size_t i = stamps_ns_.size();
        const PointCloud2Msg msg = renamedErrors(name(i), [&] { return m.pointCloud2(); });
        (void)scanFromPointCloud2(msg, name(i));
        stamps_ns_.push_back(msg.header.stamp_ns);
        if (i == 0)
            frame_id_ = msg.header.frame_id;
        else if (msg.header.frame_id != frame_id_ && other_frame_message_ == 0)
        {
            other_frame_message_ = i;
            other_frame_id_ = msg.header.frame_id;
        }
        return true;
    });
    core::require(!stamps_ns_.empty(), bag, "topic " + topic_ + " holds no message");
}

std::string BagScanSource::name(size_t i) const
{
    return bag_->path() + " topic " + topic_ + " message " + std::to_string(i);
}

std::string BagScanSource::describe() const
{
    return std::to_string(size()) + " PointCloud2 messages of " + topic_ + " in " + bag_->path() + " (" +
           bag_->describe() + ")";
}

std::vector<double> BagScanSource::stampsSeconds() const
{
    std::vector<double> s;
    for (size_t i = 0; i < size(); ++i)
    {
        core::require(stamps_ns_[i] != 0, name(i),
                      "its header stamp is unset (0): the scan has no time to look its pose up at (set scan_times = "
                      "order or file)");
        s.push_back(secondsFromNs(stamps_ns_[i]));
    }
    return s;
}

std::string BagScanSource::lidarFrame() const
{
    core::require(!frame_id_.empty(), name(0), "has no header.frame_id: the LiDAR's frame is unknown");
    core::require(other_frame_message_ == 0, name(other_frame_message_),
                  "has header.frame_id '" + other_frame_id_ + "' where message 0 has '" + frame_id_ +
                      "': the scans of one topic must share one LiDAR frame");
    return frame_id_;
}

map::LidarScan BagScanSource::decode(const BagMessage& m, size_t i) const
{
    const PointCloud2Msg msg = renamedErrors(name(i), [&] { return m.pointCloud2(); });
    core::require(msg.header.stamp_ns == stamps_ns_.at(i), name(i), "changed since the bag was opened");
    return scanFromPointCloud2(msg, name(i));
}

void BagScanSource::forEach(const std::function<void(size_t, map::LidarScan&&)>& visit) const
{
    size_t i = 0;
    bag_->read({topic_}, [&](const BagMessage& m) {
        core::require(i < size(), bag_->path(), "topic " + topic_ + " gained messages since the bag was opened");
        visit(i, decode(m, i));
        ++i;
        return true;
    });
    core::require(i == size(), bag_->path(), "topic " + topic_ + " lost messages since the bag was opened");
}

map::LidarScan BagScanSource::read(size_t i) const
{
    core::require(i < size(), name(i), "no such message");
    map::LidarScan scan;
    size_t k = 0;
    bag_->read({topic_}, [&](const BagMessage& m) {
        if (k < i) return ++k, true;
        scan = decode(m, i);
        return false;
    });
    return scan;
}

core::Trajectory readBagTrajectory(const std::string& bag_path, const std::string& topic)
{
    const std::unique_ptr<MessageSource> bag = openMessageSource(bag_path);
    requireTopic(*bag, topic, {types::kPoseStamped, types::kOdometry, types::kTransformStamped});
    core::Trajectory trajectory;
    trajectory.header = "T_world_body from " + bag_path + " topic " + topic;
    size_t i = 0;
    bag->read({topic}, [&](const BagMessage& m) {
        const std::string where = bag_path + " topic " + topic + " message " + std::to_string(i++);
        const PoseMsg p = renamedErrors(where, [&] { return m.pose(); });
        core::require(p.header.stamp_ns != 0, where, "its header stamp is unset (0)");
        core::require(p.position.allFinite() && p.orientation.coeffs().allFinite(), where, "non-finite pose");
        core::require(std::abs(p.orientation.norm() - 1.0) < 1e-2, where, "quaternion is not unit length");
        trajectory.poses.push_back(
            {secondsFromNs(p.header.stamp_ns), core::fromTranslationQuaternion(p.position, p.orientation)});
        return true;
    });
    core::require(!trajectory.poses.empty(), bag_path, "topic " + topic + " holds no message");
    std::stable_sort(trajectory.poses.begin(), trajectory.poses.end(),
                     [](const core::TimedPose& a, const core::TimedPose& b) { return a.t < b.t; });
    return trajectory;
}

BagExtrinsic readBagExtrinsic(const std::string& bag_path, const std::string& tf_topic, const std::string& body_frame,
                              const std::string& lidar_frame, const std::string& lidar_topic)
{
    const std::string frames = " (T_body_lidar from body_frame '" + body_frame + "' to the LiDAR frame '" +
                               lidar_frame + "', the header.frame_id of " + lidar_topic + ")";
    try
    {
        const std::unique_ptr<MessageSource> bag = openMessageSource(bag_path);
        const StaticTransforms tf = readStaticTransforms(*bag, tf_topic);
        BagExtrinsic e;
        e.T_body_lidar = core::toIsometry(tf.chain(body_frame, lidar_frame, bag_path + " topic " + tf_topic));
        e.chain = tf.describeChain(body_frame, lidar_frame);
        return e;
    }
    catch (const InputError& e)
    {
        throw InputError(e.input(), e.problem() + frames);
    }
}

}  // namespace quasiloc::ros
