// ROS 1 bags as a MessageSource (ros1_source.h).
#include "ros1_source.h"

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <filesystem>
#include <quasiloc/core/error.h>

#include "ros1_messages.h"
#include "ros1_point_cloud2.h"
#include "ros1_tf_message.h"

namespace fs = std::filesystem;
using quasiloc::core::InputError;

namespace quasiloc::ros
{
namespace
{
class Ros1Message : public BagMessage
{
   public:
    Ros1Message(const rosbag::MessageInstance& m, const std::string& file, const std::string& type)
        : m_(m), file_(file), topic_(m.getTopic()), type_(type)
    {}
    const std::string& topic() const override { return topic_; }
    const std::string& type() const override { return type_; }
    std::int64_t timeNs() const override { return std::int64_t(m_.getTime().toNSec()); }
    std::vector<std::uint8_t> payload() const override
    {
        std::vector<std::uint8_t> bytes(m_.size());
        ::ros::serialization::OStream stream(bytes.data(), std::uint32_t(bytes.size()));
        m_.write(stream);
        return bytes;
    }

    ImageMsg image() const override { return ros1::fromRos1(*get<sensor_msgs::Image>(types::kImage)); }
    CompressedImageMsg compressedImage() const override
    {
        return ros1::fromRos1(*get<sensor_msgs::CompressedImage>(types::kCompressedImage));
    }
    ImuMsg imu() const override { return ros1::fromRos1(*get<sensor_msgs::Imu>(types::kImu)); }
    CameraInfoMsg cameraInfo() const override
    {
        return ros1::fromRos1(*get<sensor_msgs::CameraInfo>(types::kCameraInfo));
    }
    PoseMsg pose() const override
    {
        if (type_ == types::kPoseStamped) return ros1::fromRos1(*get<geometry_msgs::PoseStamped>(type_.c_str()));
        if (type_ == types::kOdometry) return ros1::fromRos1(*get<nav_msgs::Odometry>(type_.c_str()));
        const TransformMsg t = ros1::fromRos1(*get<geometry_msgs::TransformStamped>(types::kTransformStamped));
        return PoseMsg{t.header, t.translation, t.rotation};
    }
    std::vector<TransformMsg> transforms() const override
    {
        if (type_ != types::kTFMessage && type_ != "tf/tfMessage")
            throw InputError(where(), "message type " + type_ + " where " + types::kTFMessage + " is expected");
        return ros1::transformsFromRos1(payload(), where());
    }

    PointCloud2Msg pointCloud2() const override
    {
        return ros1::fromRos1(std::move(*get<sensor_msgs::PointCloud2>(types::kPointCloud2)));
    }

   protected:
    const std::string& file() const override { return file_; }

   private:
    template <typename T>
    boost::shared_ptr<T> get(const char* expected) const
    {
        if (type_ != expected)
            throw InputError(where(), "message type " + type_ + " where " + expected + " is expected");
        try
        {
            auto p = m_.instantiate<T>();
            if (!p) throw InputError(where(), "cannot decode as " + std::string(expected));
            return p;
        }
        catch (const ::ros::Exception& e)
        {
            throw InputError(where(), std::string("cannot read the message: ") + e.what());
        }
    }

    const rosbag::MessageInstance& m_;
    const std::string& file_;
    const std::string& topic_;
    const std::string& type_;
};

class Ros1Source : public MessageSource
{
   public:
    explicit Ros1Source(const std::string& path) : path_(path)
    {
        std::error_code ec;
        if (!fs::is_regular_file(path, ec)) throw InputError(path, "bag file not found");
        bytes_ = fs::file_size(path);
        try
        {
            bag_.open(path, rosbag::bagmode::Read);
            rosbag::View all(bag_);
            for (const rosbag::ConnectionInfo* c : all.getConnections()) types_[c->topic] = c->datatype;
            if (all.size() > 0) span_ = {all.getBeginTime().toNSec(), all.getEndTime().toNSec()};
        }
        catch (const rosbag::BagException& e)
        {
            throw InputError(path, std::string("cannot read as a ROS 1 bag: ") + e.what() +
                                       " (a truncated or unindexed recording: try 'rosbag reindex')");
        }
    }
    const std::string& path() const override { return path_; }
    std::string describe() const override { return "ROS 1 bag"; }
    std::uint64_t bytes() const override { return bytes_; }
    const std::map<std::string, std::string>& topicTypes() const override { return types_; }
    std::pair<std::int64_t, std::int64_t> timeSpanNs() const override { return span_; }

    void read(const std::vector<std::string>& topics, const std::function<bool(const BagMessage&)>& visit) override
    {
        try
        {
            rosbag::View view(bag_, rosbag::TopicQuery(topics));
            for (const rosbag::MessageInstance& m : view)
                if (!visit(Ros1Message(m, path_, types_.at(m.getTopic())))) return;
        }
        catch (const rosbag::BagException& e)
        {
            throw InputError(path_, std::string("corrupt or truncated bag: ") + e.what());
        }
        catch (const ::ros::Exception& e)
        {
            throw InputError(path_, std::string("cannot read a message: ") + e.what());
        }
    }

   private:
    std::string path_;
    rosbag::Bag bag_;
    std::map<std::string, std::string> types_;
    std::uint64_t bytes_ = 0;
    std::pair<std::int64_t, std::int64_t> span_{0, 0};
};
}  // namespace

std::unique_ptr<MessageSource> openRos1Bag(const std::string& path) { return std::make_unique<Ros1Source>(path); }

}  // namespace quasiloc::ros
