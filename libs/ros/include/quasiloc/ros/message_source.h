#pragma once
// What bag2rawlog reads, whatever the bag format: the topics with their types, and the messages of some topics in
// time order, each decoded on demand into the plain structs of messages.h. A ROS 1 bag (rosbag, when the library is
// built with it) and a ROS 2 bag (rosbag2 folder, .db3 or .mcap; CDR messages) are two implementations, so the
// conversion (bag2rawlog.cpp) and the calibration from a bag (bag_calibration.h) exist once.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <quasiloc/ros/messages.h>
#include <quasiloc/ros/point_cloud2.h>
#include <string>
#include <vector>

namespace quasiloc::ros
{
/** One message of a bag. The decoders throw InputError naming where() for a message that does not decode, or
 *  whose type is not the one asked for (or not supported). */
class BagMessage
{
   public:
    virtual ~BagMessage() = default;
    virtual const std::string& topic() const = 0;
    virtual const std::string& type() const = 0;  ///< normalised ("sensor_msgs/Image")
    virtual std::int64_t timeNs() const = 0;      ///< the recorder's time (bag time, MCAP log time)
    /** The serialised message (ROS 2: CDR with its encapsulation header, after rosbag2's message decompression;
     *  ROS 1: the ROS 1 serialisation). */
    virtual std::vector<std::uint8_t> payload() const = 0;
    /** "<file> topic <topic> (message at t=<ns> ns)". */
    std::string where() const;

    virtual ImageMsg image() const = 0;
    virtual CompressedImageMsg compressedImage() const = 0;
    virtual ImuMsg imu() const = 0;
    virtual CameraInfoMsg cameraInfo() const = 0;
    /** geometry_msgs/PoseStamped, geometry_msgs/TransformStamped or nav_msgs/Odometry. */
    virtual PoseMsg pose() const = 0;
    /** tf2_msgs/TFMessage (tf/tfMessage in ROS 1). */
    virtual std::vector<TransformMsg> transforms() const = 0;
    virtual PointCloud2Msg pointCloud2() const = 0;

   protected:
    virtual const std::string& file() const = 0;
};

class MessageSource
{
   public:
    virtual ~MessageSource() = default;
    /** The path given (a file, or a rosbag2 folder). */
    virtual const std::string& path() const = 0;
    /** e.g. "ROS 1 bag", "rosbag2 sqlite3 (5 files)". */
    virtual std::string describe() const = 0;
    virtual std::uint64_t bytes() const = 0;
    /** Topic -> normalised message type. */
    virtual const std::map<std::string, std::string>& topicTypes() const = 0;
    /** The recording's first and last message times (ns), {0, 0} when unknown before reading. */
    virtual std::pair<std::int64_t, std::int64_t> timeSpanNs() const = 0;
    /** The messages of `topics` in time order (a storage's own order where it has none: MCAP chunks one after
     *  another, each chunk's messages by log time); visit returns false to stop. Corrupt or truncated storage is
     *  an InputError naming the file. */
    virtual void read(const std::vector<std::string>& topics, const std::function<bool(const BagMessage&)>& visit) = 0;
};

/** Opens a ROS 1 bag (.bag), a rosbag2 folder (metadata.yaml names the storage: sqlite3 or mcap), or one rosbag2
 *  storage file (.db3, .mcap). InputError naming the path for anything else, for an unknown storage or
 *  compression, and for a ROS 1 bag when the library was built without ROS 1 support. */
std::unique_ptr<MessageSource> openMessageSource(const std::string& path);

/** Whether this build reads and writes ROS 1 bags (Debian's librosbag-dev was found). */
bool haveRos1();

}  // namespace quasiloc::ros
