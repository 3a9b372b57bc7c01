#pragma once
// A ROS 2 bag as a MessageSource: a rosbag2 folder (metadata.yaml + its storage files, split bags too) or one
// storage file, SQLite3 (.db3, sqlite_bag.h) or MCAP (.mcap, mcap_reader.h), messages in CDR (cdr.h). The storage is
// chosen by metadata.yaml's storage_identifier, or by the file's extension and magic. rosbag2's compression:
// "message" mode (each message a zstd frame) and "file" mode (each storage file one zstd stream, decompressed to a
// temporary file that is removed afterwards).
#include <memory>
#include <quasiloc/ros/message_source.h>

namespace quasiloc::ros
{
std::unique_ptr<MessageSource> openRosbag2(const std::string& path);
}  // namespace quasiloc::ros
