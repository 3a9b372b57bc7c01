// BagWriter (bag_writer.h) over rawlog2bag's sinks.
#include <filesystem>
#include <quasiloc/core/error.h>
#include <quasiloc/ros/bag_writer.h>

#include "bag_sink.h"

namespace quasiloc::ros
{
BagWriter::BagWriter(const std::string& path, dataset::BagFormat format, dataset::BagCompression compression)
    : sink_(format == dataset::BagFormat::Mcap
                ? makeMcapBagSink(path, std::filesystem::path(path).filename().string(), compression)
                : makeRos1BagSink(path, compression))
{}

BagWriter::~BagWriter() = default;

void BagWriter::pointCloud2(const std::string& topic, const PointCloud2Msg& m) { sink_->pointCloud2(topic, m); }

void BagWriter::pose(const std::string& topic, const PoseMsg& m) { sink_->pose(topic, m); }

void BagWriter::tfStatic(const std::string& topic, const std::vector<TransformMsg>& transforms)
{
    core::require(!transforms.empty(), topic, "a TFMessage needs at least one transform");
    sink_->tfStatic(topic, transforms);
}

void BagWriter::close() { sink_->close(); }

}  // namespace quasiloc::ros
