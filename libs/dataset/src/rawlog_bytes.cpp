#include "rawlog_bytes.h"

#include <algorithm>
#include <quasiloc/core/error.h>
#include <stdexcept>

namespace quasiloc::dataset::detail
{
size_t RawlogStream::Read(void* buffer, size_t count)
{
    // An empty std::vector's data() may be null, and memcpy's arguments must not be, even for 0 bytes.
    if (count == 0) return 0;
    auto* out = static_cast<std::uint8_t*>(buffer);
    size_t done = 0;
    if (pending_at_ < pending_.size())
    {
        done = std::min(count, pending_.size() - pending_at_);
        std::memcpy(out, pending_.data() + pending_at_, done);
        pending_at_ += done;
        if (pending_at_ == pending_.size())
        {
            pending_.clear();
            pending_at_ = 0;
        }
    }
    // CFileGZInputStream::Read may return fewer bytes than asked before the end (gzread), so read on. On corrupt
    // gz data gzread returns -1, which CFileGZInputStream passes on as a size_t: stop there (a short read).
    while (done < count && !corrupt_)
    {
        const size_t n = in_.Read(out + done, count - done);
        if (n > count - done) corrupt_ = true;
        if (n == 0 || corrupt_) break;
        done += n;
    }
    consumed_ += done;
    return done;
}

size_t RawlogStream::Write(const void*, size_t) { throw std::logic_error("RawlogStream is read-only"); }

uint64_t RawlogStream::Seek(int64_t, CStream::TSeekOrigin) { throw std::logic_error("RawlogStream cannot seek"); }

void RawlogStream::pushBack(const std::vector<std::uint8_t>& bytes)
{
    std::vector<std::uint8_t> joined(bytes);
    joined.insert(joined.end(), pending_.begin() + static_cast<std::ptrdiff_t>(pending_at_), pending_.end());
    pending_ = std::move(joined);
    pending_at_ = 0;
    consumed_ -= bytes.size();
}

namespace
{
const char* const kCorruptGz = "the gz-compressed data is corrupt (zlib cannot decompress it)";
}

size_t FieldReader::readSome(void* buffer, size_t count) { return in_.Read(buffer, count); }

void FieldReader::readExactly(void* buffer, size_t count, const char* field)
{
    const size_t got = in_.Read(buffer, count);
    if (got != count && in_.corrupt()) fail(kCorruptGz);
    if (got != count)
        fail(std::string("truncated: the file ends inside ") + field + " (" + std::to_string(got) + " of " +
             std::to_string(count) + " bytes)");
}

std::string FieldReader::text(const char* field, size_t max_length)
{
    const auto length = pod<std::uint32_t>(field);
    if (length > max_length)
        fail(std::string(field) + " has a length of " + std::to_string(length) + " bytes, more than the " +
             std::to_string(max_length) + " this reader accepts (corrupt file)");
    const std::vector<std::uint8_t> b = bytes(length, field);
    return std::string(b.begin(), b.end());
}

std::vector<std::uint8_t> FieldReader::bytes(size_t count, const char* field)
{
    constexpr size_t kSlice = size_t(1) << 20;
    std::vector<std::uint8_t> out;
    while (out.size() < count)
    {
        const size_t before = out.size();
        const size_t want = std::min(kSlice, count - before);
        out.resize(before + want);
        const size_t got = in_.Read(out.data() + before, want);
        if (got != want && in_.corrupt()) fail(kCorruptGz);
        if (got != want)
            fail(std::string("truncated: ") + field + " announces " + std::to_string(count) +
                 " bytes, the file ends after " + std::to_string(before + got));
    }
    return out;
}

void FieldReader::fail(const std::string& problem) const
{
    std::string where = "entry " + std::to_string(entry_) + " (at byte " + std::to_string(entry_offset_) +
                        " of the uncompressed stream)";
    if (!context_.empty()) where += ", " + context_;
    throw core::InputError(path_, where + ": " + problem);
}

}  // namespace quasiloc::dataset::detail
