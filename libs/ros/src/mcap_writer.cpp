// MCAP writer (mcap_writer.h).
#include <algorithm>
#include <quasiloc/ros/compression.h>
#include <quasiloc/ros/mcap_reader.h>
#include <quasiloc/ros/mcap_writer.h>
#include <stdexcept>

#include "mcap_records.h"

namespace quasiloc::ros::mcap
{
namespace
{
/** Builds one record's content, little endian. */
class Record
{
   public:
    explicit Record(std::uint8_t opcode) : bytes_(kRecordHeaderBytes, 0) { bytes_[0] = opcode; }
    Record& u8(std::uint8_t v) { return le(v, 1); }
    Record& u16(std::uint16_t v) { return le(v, 2); }
    Record& u32(std::uint32_t v) { return le(v, 4); }
    Record& u64(std::uint64_t v) { return le(v, 8); }
    Record& string(const std::string& s)
    {
        u32(std::uint32_t(s.size()));
        bytes_.insert(bytes_.end(), s.begin(), s.end());
        return *this;
    }
    Record& raw(const std::uint8_t* p, std::size_t n)
    {
        bytes_.insert(bytes_.end(), p, p + n);
        return *this;
    }
    /** A u32 byte-length prefixed block (maps, arrays) built by another Record's content. */
    Record& block32(const std::vector<std::uint8_t>& content)
    {
        u32(std::uint32_t(content.size()));
        return raw(content.data(), content.size());
    }
    std::vector<std::uint8_t> content() const { return {bytes_.begin() + kRecordHeaderBytes, bytes_.end()}; }
    std::vector<std::uint8_t> take()
    {
        const std::uint64_t n = bytes_.size() - kRecordHeaderBytes;
        for (int i = 0; i < 8; ++i) bytes_[1 + std::size_t(i)] = std::uint8_t(n >> (8 * i));
        return std::move(bytes_);
    }

   private:
    Record& le(std::uint64_t v, int k)
    {
        for (int i = 0; i < k; ++i) bytes_.push_back(std::uint8_t(v >> (8 * i)));
        return *this;
    }
    std::vector<std::uint8_t> bytes_;
};
}  // namespace

Writer::Writer(const std::string& path, Options options) : path_(path), o_(std::move(options))
{
    if (o_.compression != "" && o_.compression != "zstd" && o_.compression != "lz4")
        throw std::invalid_argument("MCAP compression '" + o_.compression + "' (none, zstd or lz4)");
    file_ = std::fopen(path.c_str(), "wb");
    if (!file_) throw core::InputError(path, "cannot write");
    emit({std::begin(kMagic), std::end(kMagic)});
    emit(Record(op::kHeader).string(o_.profile).string(o_.library).take());
}

Writer::~Writer()
{
    if (file_) std::fclose(file_);
}

void Writer::emit(const std::vector<std::uint8_t>& bytes)
{
    if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size())
        throw core::InputError(path_, "cannot write (disk full?)");
    data_crc_ = crc32Of(bytes.data(), bytes.size(), data_crc_);
    offset_ += bytes.size();
}

std::uint16_t Writer::addSchema(const std::string& name, const std::string& encoding, const std::string& data)
{
    flushChunk();
    const auto id = std::uint16_t(schema_records_.size() + 1);  // 0 means "no schema"
    auto rec = Record(op::kSchema)
                   .u16(id)
                   .string(name)
                   .string(encoding)
                   .string(data)  // bytes: the same u32 length prefix
                   .take();
    emit(rec);
    schema_records_.push_back(std::move(rec));
    return id;
}

std::uint16_t Writer::addChannel(const std::string& topic, std::uint16_t schema_id, const std::string& message_encoding,
                                 const std::map<std::string, std::string>& metadata)
{
    flushChunk();
    const auto id = std::uint16_t(channel_records_.size());
    Record map(0);
    for (const auto& [k, v] : metadata) map.string(k).string(v);
    auto rec = Record(op::kChannel)
                   .u16(id)
                   .u16(schema_id)
                   .string(topic)
                   .string(message_encoding)
                   .block32(map.content())
                   .take();
    emit(rec);
    channel_records_.push_back(std::move(rec));
    return id;
}

void Writer::write(std::uint16_t channel, std::uint64_t log_time, std::uint64_t publish_time,
                   const std::vector<std::uint8_t>& data)
{
    if (chunk_.empty()) chunk_start_ = chunk_end_ = log_time;
    chunk_index_[channel].emplace_back(log_time, chunk_.size());
    const auto rec = Record(op::kMessage)
                         .u16(channel)
                         .u32(sequence_[channel]++)
                         .u64(log_time)
                         .u64(publish_time)
                         .raw(data.data(), data.size())
                         .take();
    chunk_.insert(chunk_.end(), rec.begin(), rec.end());
    chunk_start_ = std::min(chunk_start_, log_time);
    chunk_end_ = std::max(chunk_end_, log_time);
    start_time_ = message_count_ == 0 ? log_time : std::min(start_time_, log_time);
    end_time_ = std::max(end_time_, log_time);
    ++message_count_;
    ++channel_counts_[channel];
    if (chunk_.size() >= o_.chunk_bytes) flushChunk();
}

void Writer::flushChunk()
{
    if (chunk_.empty()) return;
    std::vector<std::uint8_t> packed;
    if (o_.compression == "zstd")
        packed = zstdCompress(chunk_.data(), chunk_.size(), o_.zstd_level);
    else if (o_.compression == "lz4")
        packed = lz4Compress(chunk_.data(), chunk_.size());
    const std::vector<std::uint8_t>& records = o_.compression.empty() ? chunk_ : packed;
    ChunkIndex ci{};
    ci.start_time = chunk_start_;
    ci.end_time = chunk_end_;
    ci.offset = offset_;
    ci.compressed_size = records.size();
    ci.uncompressed_size = chunk_.size();
    emit(Record(op::kChunk)
             .u64(chunk_start_)
             .u64(chunk_end_)
             .u64(chunk_.size())
             .u32(crc32Of(chunk_.data(), chunk_.size()))
             .string(o_.compression)
             .u64(records.size())
             .raw(records.data(), records.size())
             .take());
    ci.length = offset_ - ci.offset;
    const std::uint64_t index_start = offset_;
    for (auto& [channel, entries] : chunk_index_)
    {
        std::stable_sort(entries.begin(), entries.end());
        Record array(0);
        for (const auto& [t, at] : entries) array.u64(t).u64(at);
        ci.index_offsets[channel] = offset_;
        emit(Record(op::kMessageIndex).u16(channel).block32(array.content()).take());
    }
    ci.index_length = offset_ - index_start;
    chunks_.push_back(ci);
    chunk_.clear();
    chunk_index_.clear();
}

void Writer::close()
{
    if (closed_) return;
    closed_ = true;
    flushChunk();
    emit(Record(op::kDataEnd).u32(data_crc_).take());
    const std::uint64_t summary_start = offset_;
    std::uint32_t summary_crc = 0;
    std::vector<std::pair<std::uint8_t, std::pair<std::uint64_t, std::uint64_t>>> groups;
    const auto group = [&](std::uint8_t opcode, const std::vector<std::vector<std::uint8_t>>& recs) {
        if (recs.empty()) return;
        const std::uint64_t start = offset_;
        for (const auto& r : recs)
        {
            emit(r);
            summary_crc = crc32Of(r.data(), r.size(), summary_crc);
        }
        groups.push_back({opcode, {start, offset_ - start}});
    };
    group(op::kSchema, schema_records_);
    group(op::kChannel, channel_records_);
    Record counts(0);
    for (const auto& [id, n] : channel_counts_) counts.u16(id).u64(n);
    group(op::kStatistics, {Record(op::kStatistics)
                                .u64(message_count_)
                                .u16(std::uint16_t(schema_records_.size()))
                                .u32(std::uint32_t(channel_records_.size()))
                                .u32(0)
                                .u32(0)
                                .u32(std::uint32_t(chunks_.size()))
                                .u64(start_time_)
                                .u64(end_time_)
                                .block32(counts.content())
                                .take()});
    std::vector<std::vector<std::uint8_t>> indexes;
    for (const auto& c : chunks_)
    {
        Record offsets(0);
        for (const auto& [id, at] : c.index_offsets) offsets.u16(id).u64(at);
        indexes.push_back(Record(op::kChunkIndex)
                              .u64(c.start_time)
                              .u64(c.end_time)
                              .u64(c.offset)
                              .u64(c.length)
                              .block32(offsets.content())
                              .u64(c.index_length)
                              .string(o_.compression)
                              .u64(c.compressed_size)
                              .u64(c.uncompressed_size)
                              .take());
    }
    group(op::kChunkIndex, indexes);
    const std::uint64_t offsets_start = offset_;
    for (const auto& [opcode, range] : groups)
    {
        const auto r = Record(op::kSummaryOffset).u8(opcode).u64(range.first).u64(range.second).take();
        emit(r);
        summary_crc = crc32Of(r.data(), r.size(), summary_crc);
    }
    auto footer = Record(op::kFooter).u64(summary_start).u64(offsets_start).u32(0).take();
    summary_crc = crc32Of(footer.data(), footer.size() - 4, summary_crc);  // up to summary_offset_start
    for (int i = 0; i < 4; ++i) footer[footer.size() - 4 + std::size_t(i)] = std::uint8_t(summary_crc >> (8 * i));
    emit(footer);
    emit({std::begin(kMagic), std::end(kMagic)});
    if (std::fclose(file_) != 0)
    {
        file_ = nullptr;
        throw core::InputError(path_, "cannot write (disk full?)");
    }
    file_ = nullptr;
}

}  // namespace quasiloc::ros::mcap
