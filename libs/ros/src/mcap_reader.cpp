// MCAP reader (mcap_reader.h).
#include <algorithm>
#include <filesystem>
#include <quasiloc/ros/compression.h>
#include <quasiloc/ros/mcap_reader.h>

#include "mcap_records.h"

using quasiloc::core::InputError;

namespace quasiloc::ros::mcap
{
const std::uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};

namespace
{
constexpr std::uint64_t kFooterRecordBytes = kRecordHeaderBytes + kFooterContentBytes;
/** The largest chunk we decompress: writers close a chunk at a few MB, and one message larger than that (a raw 8K
 *  16-bit image is 100 MB) gets a chunk of its own. */
constexpr std::uint64_t kMaxChunkBytes = std::uint64_t(512) << 20;
}  // namespace

Reader::Reader(std::string path) : path_(std::move(path))
{
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path_, ec)) throw InputError(path_, "MCAP file not found");
    file_ = std::fopen(path_.c_str(), "rb");
    if (!file_) throw InputError(path_, "cannot open");
    size_ = std::filesystem::file_size(path_);
    std::uint8_t magic[8];
    if (size_ < 8) throw InputError(path_, "not an MCAP file (" + std::to_string(size_) + " bytes)");
    readAt(0, magic, 8, "the magic");
    if (!std::equal(magic, magic + 8, kMagic)) throw InputError(path_, "not an MCAP file (no MCAP magic at byte 0)");
    readFooterAndSummary();
}

Reader::~Reader()
{
    if (file_) std::fclose(file_);
}

std::string Reader::where(std::uint64_t at) const
{
    return path_ + " (MCAP record at byte " + std::to_string(at) + ")";
}

void Reader::readAt(std::uint64_t offset, std::uint8_t* out, std::size_t n, const char* what)
{
    if (offset > size_ || n > size_ - offset)
        throw InputError(path_, std::string("truncated: ") + what + " at byte " + std::to_string(offset) +
                                    " runs past the end of the file (" + std::to_string(size_) + " bytes)");
    if (fseeko(file_, off_t(offset), SEEK_SET) != 0 || std::fread(out, 1, n, file_) != n)
        throw InputError(path_, std::string("cannot read ") + what + " at byte " + std::to_string(offset));
}

std::string Reader::typeOf(const Channel& c) const
{
    const auto it = schemas_.find(c.schema_id);
    return it == schemas_.end() ? std::string() : it->second.name;
}

void Reader::readFooterAndSummary()
{
    if (size_ < 8 + kFooterRecordBytes + 8)
        throw InputError(path_,
                         "truncated: too short for an MCAP file with its footer (" + std::to_string(size_) + " bytes)");
    std::uint8_t tail[kFooterRecordBytes + 8];
    const std::uint64_t footer_at = size_ - sizeof tail;
    readAt(footer_at, tail, sizeof tail, "the footer");
    if (!std::equal(tail + kFooterRecordBytes, tail + sizeof tail, kMagic) || tail[0] != op::kFooter)
        throw InputError(path_,
                         "truncated: no MCAP footer and end magic (a recording that was cut off; the "
                         "mcap CLI's 'recover' command can rewrite it)");
    Cursor c(tail + 1, kFooterRecordBytes - 1, where(footer_at));
    if (c.u64() != kFooterContentBytes) throw InputError(where(footer_at), "footer of the wrong length");
    const std::uint64_t summary_start = c.u64();
    c.u64();  // summary_offset_start: the summary is read whole, its offsets are not needed
    const std::uint32_t crc = c.u32();
    const std::uint64_t crc_end = footer_at + kRecordHeaderBytes + 16;  // up to and including summary_offset_start
    if (summary_start != 0 && (summary_start < 8 || summary_start > footer_at))
        throw InputError(where(footer_at),
                         "footer's summary_start " + std::to_string(summary_start) + " is outside the file");
    readSummary(summary_start, footer_at, crc, crc_end);
}

void Reader::readSummary(std::uint64_t start, std::uint64_t end, std::uint32_t crc, std::uint64_t crc_end)
{
    const std::uint64_t crc_start = start != 0 ? start : end;
    std::vector<std::uint8_t> bytes(std::size_t(crc_end - crc_start));
    readAt(crc_start, bytes.data(), bytes.size(), "the summary section");
    if (crc != 0)
    {
        const std::uint32_t actual = crc32Of(bytes.data(), bytes.size());
        if (actual != crc)
            throw InputError(path_, "summary CRC mismatch (footer says " + std::to_string(crc) + ", the bytes give " +
                                        std::to_string(actual) + "): a corrupt file");
        stats_.summary_crc_checked = true;
    }
    if (start == 0) return;
    summary_.present = true;
    const std::size_t n = std::size_t(end - start);
    std::size_t pos = 0;
    while (pos < n)
    {
        const std::uint64_t at = start + pos;
        Cursor h(bytes.data() + pos, n - pos, where(at));
        const std::uint8_t opcode = h.u8();
        const std::uint64_t len = h.u64();
        if (len > n - pos - kRecordHeaderBytes) throw InputError(where(at), "summary record runs past its section");
        const std::uint8_t* p = bytes.data() + pos + kRecordHeaderBytes;
        if (opcode == op::kSchema)
            addSchema(p, std::size_t(len), at);
        else if (opcode == op::kChannel)
            addChannel(p, std::size_t(len), at);
        else if (opcode == op::kChunkIndex)
            ++summary_.chunk_indexes;
        else if (opcode == op::kStatistics)
        {
            Cursor c(p, std::size_t(len), where(at));
            summary_.has_statistics = true;
            summary_.message_count = c.u64();
            c.u16();                              // schema_count
            for (int i = 0; i < 4; ++i) c.u32();  // channel, attachment, metadata, chunk counts
            c.u64();                              // message_start_time
            c.u64();                              // message_end_time
            const std::uint8_t* counts = c.bytes32();
            Cursor m(counts, c.lastSize(), where(at));
            while (m.remaining() > 0)
            {
                const std::uint16_t id = m.u16();
                summary_.channel_message_counts[id] = m.u64();
            }
        }
        pos += kRecordHeaderBytes + std::size_t(len);
    }
}

void Reader::addSchema(const std::uint8_t* p, std::size_t n, std::uint64_t at)
{
    Cursor c(p, n, where(at));
    Schema s;
    s.id = c.u16();
    s.name = c.string();
    s.encoding = c.string();
    const std::uint8_t* d = c.bytes32();
    s.data.assign(reinterpret_cast<const char*>(d), c.lastSize());
    if (s.id == 0) throw InputError(where(at), "schema id 0 is reserved");
    schemas_[s.id] = std::move(s);
}

void Reader::addChannel(const std::uint8_t* p, std::size_t n, std::uint64_t at)
{
    Cursor c(p, n, where(at));
    Channel ch;
    ch.id = c.u16();
    ch.schema_id = c.u16();
    ch.topic = c.string();
    ch.message_encoding = c.string();
    c.bytes32();  // metadata map (rosbag2 keeps the QoS profiles there)
    channels_[ch.id] = std::move(ch);
}

MessageView Reader::message(const std::uint8_t* p, std::size_t n, std::uint64_t at) const
{
    Cursor c(p, n, where(at));
    MessageView m;
    const std::uint16_t channel = c.u16();
    m.sequence = c.u32();
    m.log_time = c.u64();
    m.publish_time = c.u64();
    m.data = c.rest();
    m.size = c.lastSize();
    const auto it = channels_.find(channel);
    if (it == channels_.end())
        throw InputError(
            where(at), "message on channel " + std::to_string(channel) + " that no Channel record declared before it");
    m.channel = &it->second;
    return m;
}

bool Reader::processChunk(const std::uint8_t* p, std::size_t n, std::uint64_t at,
                          const std::function<bool(const MessageView&)>& visit)
{
    const std::string w = path_ + " (MCAP chunk at byte " + std::to_string(at) + ")";
    Cursor c(p, n, w);
    c.u64();  // message_start_time
    c.u64();  // message_end_time
    const std::uint64_t uncompressed_size = c.u64();
    const std::uint32_t uncompressed_crc = c.u32();
    const std::string compression = c.string();
    const std::uint8_t* records = c.bytes64();
    std::size_t records_size = c.lastSize();
    if (uncompressed_size > kMaxChunkBytes)
        throw InputError(w, "chunk of " + std::to_string(uncompressed_size) + " bytes uncompressed, more than the " +
                                std::to_string(kMaxChunkBytes >> 20) + " MB we read");
    std::vector<std::uint8_t> inflated;
    if (compression == "zstd")
        inflated = zstdDecompress(records, records_size, std::size_t(uncompressed_size), w);
    else if (compression == "lz4")
        inflated = lz4Decompress(records, records_size, std::size_t(uncompressed_size), w);
    else if (!compression.empty())
        throw InputError(w, "unknown chunk compression '" + compression + "' (none, zstd and lz4 are specified)");
    if (!compression.empty())
    {
        records = inflated.data();
        records_size = inflated.size();
    }
    if (records_size != uncompressed_size)
        throw InputError(w, "chunk holds " + std::to_string(records_size) + " bytes of records, its header says " +
                                std::to_string(uncompressed_size));
    if (uncompressed_crc != 0)
    {
        const std::uint32_t actual = crc32Of(records, records_size);
        if (actual != uncompressed_crc)
            throw InputError(w, "chunk CRC mismatch (header " + std::to_string(uncompressed_crc) + ", records " +
                                    std::to_string(actual) + "): a corrupt file");
        ++stats_.chunk_crcs_checked;
    }
    ++stats_.chunks;
    ++stats_.compressions[compression];
    std::vector<MessageView> messages;
    std::size_t pos = 0;
    while (pos < records_size)
    {
        Cursor h(records + pos, records_size - pos, w);
        const std::uint8_t opcode = h.u8();
        const std::uint64_t len = h.u64();
        if (len > records_size - pos - kRecordHeaderBytes)
            throw InputError(w, "a record inside the chunk runs past its end");
        const std::uint8_t* rp = records + pos + kRecordHeaderBytes;
        if (opcode == op::kSchema)
            addSchema(rp, std::size_t(len), at);
        else if (opcode == op::kChannel)
            addChannel(rp, std::size_t(len), at);
        else if (opcode == op::kMessage)
            messages.push_back(message(rp, std::size_t(len), at));
        pos += kRecordHeaderBytes + std::size_t(len);
    }
    std::stable_sort(messages.begin(), messages.end(),
                     [](const MessageView& a, const MessageView& b) { return a.log_time < b.log_time; });
    for (const auto& m : messages)
    {
        ++stats_.messages;
        if (!visit(m)) return false;
    }
    return true;
}

bool Reader::processRecord(std::uint8_t opcode, const std::uint8_t* p, std::size_t n, std::uint64_t at,
                           const std::function<bool(const MessageView&)>& visit)
{
    switch (opcode)
    {
        case op::kHeader:
        {
            Cursor c(p, n, where(at));
            profile_ = c.string();
            library_ = c.string();
            return true;
        }
        case op::kSchema: addSchema(p, n, at); return true;
        case op::kChannel: addChannel(p, n, at); return true;
        case op::kMessage:
        {
            ++stats_.messages;
            return visit(message(p, n, at));
        }
        case op::kChunk: return processChunk(p, n, at, visit);
        default: return true;  // indexes, attachments, metadata and unknown records: not needed
    }
}

void Reader::readMessages(const std::function<bool(const MessageView&)>& visit)
{
    std::uint64_t pos = 8;
    std::uint32_t crc = crc32Of(kMagic, 8);
    std::vector<std::uint8_t> record;
    for (;;)
    {
        std::uint8_t head[kRecordHeaderBytes];
        readAt(pos, head, sizeof head, "a record header");
        Cursor h(head, sizeof head, where(pos));
        const std::uint8_t opcode = h.u8();
        const std::uint64_t len = h.u64();
        if (opcode == op::kFooter) return;  // no DataEnd record (written before the specification had it)
        if (len > size_ - pos - kRecordHeaderBytes)
            throw InputError(where(pos), "truncated: the record of " + std::to_string(len) +
                                             " bytes runs past the end of the file (" + std::to_string(size_) +
                                             " bytes): a recording that was cut off");
        record.resize(std::size_t(len));
        readAt(pos + kRecordHeaderBytes, record.data(), record.size(), "a record");
        if (opcode == op::kDataEnd)
        {
            Cursor c(record.data(), record.size(), where(pos));
            const std::uint32_t expected = c.u32();
            if (expected != 0 && expected != crc)
                throw InputError(where(pos), "data section CRC mismatch (DataEnd says " + std::to_string(expected) +
                                                 ", the bytes give " + std::to_string(crc) + "): a corrupt file");
            stats_.data_crc_checked = expected != 0;
            return;
        }
        crc = crc32Of(head, sizeof head, crc);
        crc = crc32Of(record.data(), record.size(), crc);
        if (pos == 8 && opcode != op::kHeader) throw InputError(where(pos), "the first record is not a Header");
        if (!processRecord(opcode, record.data(), record.size(), pos, visit)) return;
        pos += kRecordHeaderBytes + len;
    }
}

}  // namespace quasiloc::ros::mcap
