// rawlog2bag's rosbag2 MCAP output (bag_sink.h): one MCAP file of CDR messages and the metadata.yaml that
// `ros2 bag info` / `ros2 bag play` read.
#include <filesystem>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/ros/cdr.h>
#include <quasiloc/ros/mcap_writer.h>
#include <quasiloc/ros/point_cloud2.h>
#include <quasiloc/ros/rosbag2_metadata.h>

#include "bag_sink.h"
#include "ros2_msg_definitions.h"

namespace fs = std::filesystem;

namespace quasiloc::ros
{
namespace
{
class McapBagSink : public BagSink
{
   public:
    McapBagSink(const std::string& folder, const std::string& name, dataset::BagCompression compression)
        : folder_(folder),
          file_name_(name + "_0.mcap"),
          writer_((fs::path(folder) / file_name_).string(), options(compression))
    {}
    bool carriesCalibration() const override { return true; }
    void image(const std::string& topic, const ImageMsg& m) override
    {
        put(topic, "sensor_msgs/msg/Image", m.header, cdr::encode(m));
    }
    void compressedImage(const std::string& topic, const CompressedImageMsg& m) override
    {
        put(topic, "sensor_msgs/msg/CompressedImage", m.header, cdr::encode(m));
    }
    void imu(const std::string& topic, const ImuMsg& m) override
    {
        put(topic, "sensor_msgs/msg/Imu", m.header, cdr::encode(m));
    }
    void pose(const std::string& topic, const PoseMsg& m) override
    {
        put(topic, "geometry_msgs/msg/PoseStamped", m.header, cdr::encode(m));
    }
    void cameraInfo(const std::string& topic, const CameraInfoMsg& m) override
    {
        put(topic, "sensor_msgs/msg/CameraInfo", m.header, cdr::encode(m));
    }
    void tfStatic(const std::string& topic, const std::vector<TransformMsg>& t) override
    {
        put(topic, "tf2_msgs/msg/TFMessage", t.at(0).header, cdr::encodeTFMessage(t));
    }
    void pointCloud2(const std::string& topic, const PointCloud2Msg& m) override
    {
        put(topic, "sensor_msgs/msg/PointCloud2", m.header, cdr::encode(m));
    }
    void close() override
    {
        writer_.close();
        Rosbag2Metadata m;
        m.storage_identifier = "mcap";
        m.relative_file_paths = {file_name_};
        m.starting_time_ns = std::int64_t(writer_.startTime());
        m.duration_ns = std::int64_t(writer_.endTime() - writer_.startTime());
        m.message_count = writer_.messageCount();
        for (const auto& [topic, channel] : channels_)
            m.topics.push_back(
                {topic, types_.at(topic), "cdr",
                 writer_.channelMessageCounts().count(channel) ? writer_.channelMessageCounts().at(channel) : 0});
        core::writeTextFileAtomically((fs::path(folder_) / "metadata.yaml").string(), rosbag2MetadataYaml(m));
    }

   private:
    static mcap::Writer::Options options(dataset::BagCompression c)
    {
        mcap::Writer::Options o;
        o.compression = c == dataset::BagCompression::Zstd ? "zstd" : c == dataset::BagCompression::Lz4 ? "lz4" : "";
        return o;
    }

    void put(const std::string& topic, const std::string& type, const MsgHeader& header,
             const std::vector<std::uint8_t>& bytes)
    {
        auto it = channels_.find(topic);
        if (it == channels_.end())
        {
            auto schema = schemas_.find(type);
            if (schema == schemas_.end())
                schema = schemas_.emplace(type, writer_.addSchema(type, "ros2msg", ros2MessageDefinition(type))).first;
            it = channels_
                     .emplace(topic, writer_.addChannel(topic, schema->second, "cdr", {{"offered_qos_profiles", ""}}))
                     .first;
            types_[topic] = type;
        }
        const auto t = std::uint64_t(header.stamp_ns);
        writer_.write(it->second, t, t, bytes);
    }

    std::string folder_, file_name_;
    mcap::Writer writer_;
    std::map<std::string, std::uint16_t> schemas_, channels_;
    std::map<std::string, std::string> types_;
};
}  // namespace

std::unique_ptr<BagSink> makeMcapBagSink(const std::string& folder, const std::string& name,
                                         dataset::BagCompression compression)
{
    fs::create_directories(folder);
    return std::make_unique<McapBagSink>(folder, name, compression);
}

}  // namespace quasiloc::ros
