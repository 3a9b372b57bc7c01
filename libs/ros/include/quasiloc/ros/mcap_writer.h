#pragma once
// An MCAP writer (https://mcap.dev/spec): messages in chunks (none, zstd or lz4, with their CRC), a message index
// per chunk and channel, a DataEnd record with the data section CRC, and a summary (schemas, channels, statistics,
// chunk indexes, summary offsets) with its CRC: what `ros2 bag info`, `mcap info` and Foxglove read without
// scanning the file.
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

namespace quasiloc::ros::mcap
{
class Writer
{
   public:
    struct Options
    {
        std::string profile = "ros2";
        std::string library = "quasiloc rawlog2bag";
        std::string compression = "zstd";   ///< "", "zstd" or "lz4"
        std::size_t chunk_bytes = 4 << 20;  ///< a chunk is closed when its records exceed this
        int zstd_level = 3;
    };
    Writer(const std::string& path, Options options);
    ~Writer();
    Writer(const Writer&) = delete;
    Writer& operator=(const Writer&) = delete;

    std::uint16_t addSchema(const std::string& name, const std::string& encoding, const std::string& data);
    std::uint16_t addChannel(const std::string& topic, std::uint16_t schema_id, const std::string& message_encoding,
                             const std::map<std::string, std::string>& metadata);
    void write(std::uint16_t channel, std::uint64_t log_time, std::uint64_t publish_time,
               const std::vector<std::uint8_t>& data);
    /** Writes the last chunk, the summary and the footer. */
    void close();

    std::uint64_t messageCount() const { return message_count_; }
    std::uint64_t startTime() const { return start_time_; }
    std::uint64_t endTime() const { return end_time_; }
    const std::map<std::uint16_t, std::uint64_t>& channelMessageCounts() const { return channel_counts_; }

   private:
    struct ChunkIndex
    {
        std::uint64_t start_time, end_time, offset, length, index_length, compressed_size, uncompressed_size;
        std::map<std::uint16_t, std::uint64_t> index_offsets;
    };
    void emit(const std::vector<std::uint8_t>& bytes);
    void flushChunk();

    std::string path_;
    Options o_;
    std::FILE* file_ = nullptr;
    std::uint64_t offset_ = 0;
    std::uint32_t data_crc_ = 0;
    std::vector<std::vector<std::uint8_t>> schema_records_, channel_records_;
    std::vector<std::uint8_t> chunk_;  ///< records of the open chunk
    std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index_;
    std::uint64_t chunk_start_ = 0, chunk_end_ = 0;
    std::vector<ChunkIndex> chunks_;
    std::map<std::uint16_t, std::uint32_t> sequence_;
    std::map<std::uint16_t, std::uint64_t> channel_counts_;
    std::uint64_t message_count_ = 0, start_time_ = 0, end_time_ = 0;
    bool closed_ = false;
};

}  // namespace quasiloc::ros::mcap
