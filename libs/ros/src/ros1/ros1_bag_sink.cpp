// rawlog2bag's ROS 1 output (bag_sink.h), through Debian's rosbag library.
#include <rosbag/bag.h>

#include <map>
#include <quasiloc/core/error.h>

#include "../bag_sink.h"
#include "ros1_messages.h"
#include "ros1_point_cloud2.h"
#include "ros1_tf_message.h"

namespace quasiloc::ros
{
namespace
{
class Ros1BagSink : public BagSink
{
   public:
    Ros1BagSink(const std::string& path, dataset::BagCompression c) : path_(path)
    {
        try
        {
            bag_.open(path, rosbag::bagmode::Write);
            bag_.setCompression(c == dataset::BagCompression::Bz2   ? rosbag::compression::BZ2
                                : c == dataset::BagCompression::Lz4 ? rosbag::compression::LZ4
                                                                    : rosbag::compression::Uncompressed);
        }
        catch (const rosbag::BagException& e)
        {
            throw core::InputError(path, std::string("cannot write the bag: ") + e.what());
        }
    }
    /** rawlog2bag's ROS 1 bags carry no CameraInfo: the Kalibr files beside the bag carry the calibration. */
    bool carriesCalibration() const override { return false; }
    void image(const std::string& topic, const ImageMsg& m) override { put(topic, ros1::toRos1(m, seq(topic))); }
    void compressedImage(const std::string& topic, const CompressedImageMsg& m) override
    {
        put(topic, ros1::toRos1(m, seq(topic)));
    }
    void imu(const std::string& topic, const ImuMsg& m) override { put(topic, ros1::toRos1(m, seq(topic))); }
    void pose(const std::string& topic, const PoseMsg& m) override { put(topic, ros1::toRos1(m, seq(topic))); }
    void cameraInfo(const std::string&, const CameraInfoMsg&) override {}
    void tfStatic(const std::string& topic, const std::vector<TransformMsg>& t) override
    {
        const ros1::TFMessage m = ros1::toRos1(t);
        try
        {
            bag_.write(topic, m.transforms.at(0).header.stamp, m);
        }
        catch (const rosbag::BagException& e)
        {
            throw core::InputError(path_, std::string("cannot write the bag: ") + e.what());
        }
    }
    void pointCloud2(const std::string& topic, const PointCloud2Msg& m) override
    {
        put(topic, ros1::toRos1(m, seq(topic)));
    }
    void close() override
    {
        try
        {
            bag_.close();
        }
        catch (const rosbag::BagException& e)
        {
            throw core::InputError(path_, std::string("cannot write the bag: ") + e.what());
        }
    }

   private:
    std::uint32_t seq(const std::string& topic) { return seq_[topic]++; }
    template <typename M>
    void put(const std::string& topic, const M& msg)
    {
        try
        {
            bag_.write(topic, msg.header.stamp, msg);
        }
        catch (const rosbag::BagException& e)
        {
            throw core::InputError(path_, std::string("cannot write the bag: ") + e.what());
        }
    }

    std::string path_;
    rosbag::Bag bag_;
    std::map<std::string, std::uint32_t> seq_;
};
}  // namespace

std::unique_ptr<BagSink> makeRos1BagSink(const std::string& path, dataset::BagCompression compression)
{
    return std::make_unique<Ros1BagSink>(path, compression);
}

}  // namespace quasiloc::ros
