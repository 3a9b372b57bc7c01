// metadata.yaml of a rosbag2 folder (rosbag2_metadata.h).
#include <yaml-cpp/yaml.h>

#include <quasiloc/core/error.h>
#include <quasiloc/ros/rosbag2_metadata.h>
#include <sstream>

using quasiloc::core::InputError;

namespace quasiloc::ros
{
namespace
{
template <typename T>
T scalar(const YAML::Node& n, const T& fallback)
{
    return n && n.IsScalar() ? n.as<T>() : fallback;
}
}  // namespace

Rosbag2Metadata readRosbag2Metadata(const std::string& yaml_path)
{
    Rosbag2Metadata m;
    try
    {
        const YAML::Node root = YAML::LoadFile(yaml_path);
        const YAML::Node info = root["rosbag2_bagfile_information"];
        if (!info || !info.IsMap())
            throw InputError(yaml_path, "no rosbag2_bagfile_information: not a rosbag2 metadata.yaml");
        m.version = scalar<int>(info["version"], 0);
        m.storage_identifier = scalar<std::string>(info["storage_identifier"], "");
        if (const auto files = info["relative_file_paths"]; files && files.IsSequence())
            for (const auto& f : files) m.relative_file_paths.push_back(f.as<std::string>());
        if (const auto d = info["duration"]; d && d.IsMap()) m.duration_ns = scalar<std::int64_t>(d["nanoseconds"], 0);
        if (const auto s = info["starting_time"]; s && s.IsMap())
            m.starting_time_ns = scalar<std::int64_t>(s["nanoseconds_since_epoch"], 0);
        m.message_count = scalar<std::uint64_t>(info["message_count"], 0);
        if (const auto topics = info["topics_with_message_count"]; topics && topics.IsSequence())
            for (const auto& t : topics)
            {
                Rosbag2Metadata::Topic topic;
                const auto md = t["topic_metadata"];
                if (!md || !md.IsMap()) throw InputError(yaml_path, "topics_with_message_count without topic_metadata");
                topic.name = scalar<std::string>(md["name"], "");
                topic.type = scalar<std::string>(md["type"], "");
                topic.serialization_format = scalar<std::string>(md["serialization_format"], "cdr");
                topic.message_count = scalar<std::uint64_t>(t["message_count"], 0);
                m.topics.push_back(topic);
            }
        m.compression_format = scalar<std::string>(info["compression_format"], "");
        m.compression_mode = scalar<std::string>(info["compression_mode"], "");
    }
    catch (const YAML::Exception& e)
    {
        throw InputError(yaml_path, std::string("not a readable rosbag2 metadata.yaml: ") + e.what());
    }
    if (m.storage_identifier.empty())
        throw InputError(yaml_path, "rosbag2_bagfile_information.storage_identifier is missing");
    if (m.relative_file_paths.empty())
        throw InputError(yaml_path, "rosbag2_bagfile_information.relative_file_paths is missing or empty");
    return m;
}

std::string rosbag2MetadataYaml(const Rosbag2Metadata& m)
{
    YAML::Emitter out;
    out << YAML::BeginMap << YAML::Key << "rosbag2_bagfile_information" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "version" << YAML::Value << m.version;
    out << YAML::Key << "storage_identifier" << YAML::Value << m.storage_identifier;
    out << YAML::Key << "duration" << YAML::Value << YAML::BeginMap << YAML::Key << "nanoseconds" << YAML::Value
        << m.duration_ns << YAML::EndMap;
    out << YAML::Key << "starting_time" << YAML::Value << YAML::BeginMap << YAML::Key << "nanoseconds_since_epoch"
        << YAML::Value << m.starting_time_ns << YAML::EndMap;
    out << YAML::Key << "message_count" << YAML::Value << m.message_count;
    out << YAML::Key << "topics_with_message_count" << YAML::Value << YAML::BeginSeq;
    for (const auto& t : m.topics)
    {
        out << YAML::BeginMap << YAML::Key << "topic_metadata" << YAML::Value << YAML::BeginMap;
        out << YAML::Key << "name" << YAML::Value << t.name << YAML::Key << "type" << YAML::Value << t.type;
        out << YAML::Key << "serialization_format" << YAML::Value << t.serialization_format;
        out << YAML::Key << "offered_qos_profiles" << YAML::Value << YAML::DoubleQuoted << "" << YAML::EndMap;
        out << YAML::Key << "message_count" << YAML::Value << t.message_count << YAML::EndMap;
    }
    out << YAML::EndSeq;
    out << YAML::Key << "compression_format" << YAML::Value << YAML::DoubleQuoted << m.compression_format;
    out << YAML::Key << "compression_mode" << YAML::Value << YAML::DoubleQuoted << m.compression_mode;
    out << YAML::Key << "relative_file_paths" << YAML::Value << YAML::BeginSeq;
    for (const auto& f : m.relative_file_paths) out << f;
    out << YAML::EndSeq;
    out << YAML::Key << "files" << YAML::Value << YAML::BeginSeq;
    for (const auto& f : m.relative_file_paths)
        out << YAML::BeginMap << YAML::Key << "path" << YAML::Value << f << YAML::Key << "starting_time" << YAML::Value
            << YAML::BeginMap << YAML::Key << "nanoseconds_since_epoch" << YAML::Value << m.starting_time_ns
            << YAML::EndMap << YAML::Key << "duration" << YAML::Value << YAML::BeginMap << YAML::Key << "nanoseconds"
            << YAML::Value << m.duration_ns << YAML::EndMap << YAML::Key << "message_count" << YAML::Value
            << m.message_count << YAML::EndMap;
    out << YAML::EndSeq;
    out << YAML::EndMap << YAML::EndMap;
    return std::string(out.c_str()) + "\n";
}

}  // namespace quasiloc::ros
