#pragma once
// A rosbag2 folder's metadata.yaml (rosbag2_bagfile_information, versions 1 to 9): which storage plugin wrote the
// files, the files in order, the compression, the topics with their message counts. Read with yaml-cpp.
#include <cstdint>
#include <string>
#include <vector>

namespace quasiloc::ros
{
struct Rosbag2Metadata
{
    struct Topic
    {
        std::string name, type, serialization_format = "cdr";
        std::uint64_t message_count = 0;
    };
    int version = 5;
    std::string storage_identifier;                ///< "sqlite3" or "mcap"
    std::vector<std::string> relative_file_paths;  ///< as written (relative to the folder)
    std::int64_t starting_time_ns = 0, duration_ns = 0;
    std::uint64_t message_count = 0;
    std::vector<Topic> topics;
    std::string compression_format, compression_mode;  ///< "" / "zstd"; "" / "FILE" / "MESSAGE"
};

/** InputError naming the file and the key for a file that is not a rosbag2 metadata.yaml. */
Rosbag2Metadata readRosbag2Metadata(const std::string& yaml_path);
/** The YAML text of `m` (version 5: what ros2 bag info of Humble and later opens). */
std::string rosbag2MetadataYaml(const Rosbag2Metadata& m);

}  // namespace quasiloc::ros
