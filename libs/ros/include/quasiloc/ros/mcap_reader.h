#pragma once
// A reader of MCAP files (https://mcap.dev/spec), written from the published specification: the format of
// rosbag2's default storage since ROS 2 Iron. No Debian package provides an MCAP library.
//
// The data section is read linearly, record by record (a file needs no summary or index to be read); chunks are
// decompressed (none, "zstd", "lz4") and their uncompressed CRC checked when it is not zero; the data section CRC
// (DataEnd) likewise. The footer and, when present, the summary section (schemas, channels, statistics) are read
// when the file is opened, the summary CRC checked when not zero. Any violation (a bad magic, a record running past
// the end of the file, a CRC mismatch, an unknown compression, a message on an undeclared channel) is an InputError
// naming the file and the byte offset.
#include <cstdint>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace quasiloc::ros::mcap
{
struct Schema
{
    std::uint16_t id = 0;
    std::string name, encoding;  ///< e.g. "sensor_msgs/msg/Image", "ros2msg"
    std::string data;
};

struct Channel
{
    std::uint16_t id = 0, schema_id = 0;
    std::string topic, message_encoding;  ///< e.g. "/cam0/image_raw", "cdr"
};

struct MessageView
{
    const Channel* channel = nullptr;
    std::uint32_t sequence = 0;
    std::uint64_t log_time = 0, publish_time = 0;  ///< ns
    const std::uint8_t* data = nullptr;
    std::size_t size = 0;
};

struct Summary
{
    bool present = false;  ///< the footer points at a summary section
    bool has_statistics = false;
    std::uint64_t message_count = 0;  ///< from Statistics
    std::map<std::uint16_t, std::uint64_t> channel_message_counts;
    std::size_t chunk_indexes = 0;
};

/** What a full read met (for tests and reports). */
struct ReadStats
{
    std::size_t chunks = 0, messages = 0, chunk_crcs_checked = 0;
    bool data_crc_checked = false, summary_crc_checked = false;
    std::map<std::string, std::size_t> compressions;  ///< chunk count per compression ("" = none)
};

class Reader
{
   public:
    explicit Reader(std::string path);
    ~Reader();
    Reader(const Reader&) = delete;
    Reader& operator=(const Reader&) = delete;

    const std::string& path() const { return path_; }
    const std::string& profile() const { return profile_; }
    const std::string& library() const { return library_; }
    const Summary& summary() const { return summary_; }
    /** The schemas and channels known so far: all of them after the constructor when the file has a summary,
     *  else those met by readMessages. */
    const std::map<std::uint16_t, Schema>& schemas() const { return schemas_; }
    const std::map<std::uint16_t, Channel>& channels() const { return channels_; }
    /** The schema name of a channel ("" when it has none). */
    std::string typeOf(const Channel& c) const;

    /** Every message of the data section in file order (those of one chunk sorted by log time); visit returns
     *  false to stop early (then the data section CRC is not checked). */
    void readMessages(const std::function<bool(const MessageView&)>& visit);
    const ReadStats& stats() const { return stats_; }

   private:
    void readFooterAndSummary();
    void readSummary(std::uint64_t start, std::uint64_t end, std::uint32_t crc, std::uint64_t crc_end);
    bool processRecord(std::uint8_t op, const std::uint8_t* p, std::size_t n, std::uint64_t at,
                       const std::function<bool(const MessageView&)>& visit);
    bool processChunk(const std::uint8_t* p, std::size_t n, std::uint64_t at,
                      const std::function<bool(const MessageView&)>& visit);
    void addSchema(const std::uint8_t* p, std::size_t n, std::uint64_t at);
    void addChannel(const std::uint8_t* p, std::size_t n, std::uint64_t at);
    MessageView message(const std::uint8_t* p, std::size_t n, std::uint64_t at) const;
    void readAt(std::uint64_t offset, std::uint8_t* out, std::size_t n, const char* what);
    std::string where(std::uint64_t at) const;

    std::string path_, profile_, library_;
    std::FILE* file_ = nullptr;
    std::uint64_t size_ = 0;
    Summary summary_;
    std::map<std::uint16_t, Schema> schemas_;
    std::map<std::uint16_t, Channel> channels_;
    ReadStats stats_;
};

/** The 8 bytes every MCAP file starts and ends with. */
extern const std::uint8_t kMagic[8];

}  // namespace quasiloc::ros::mcap
