#pragma once
// The byte level of the validating rawlog reader (rawlog_entries.h): the decompressed stream, and checked reads
// of the fields of MRPT's archive format. Every problem is an InputError naming the file, the entry, the byte
// offset and the field; nothing is allocated from a length field before its bytes have arrived.
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CStream.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

namespace quasiloc::dataset::detail
{
/** The decompressed bytes of a rawlog (plain or gz: CFileGZInputStream reads both) as an mrpt::io::CStream that
 *  counts what was consumed and takes bytes back in front. The scanner reads an object's header itself; when
 *  MRPT must read an object of a class the scanner does not know, the header goes back and MRPT reads the whole
 *  object from here. Read-only and forward-only. */
class RawlogStream : public mrpt::io::CStream
{
   public:
    explicit RawlogStream(mrpt::io::CFileGZInputStream& in) : in_(in) {}

    size_t Read(void* buffer, size_t count) override;
    size_t Write(const void*, size_t) override;
    uint64_t Seek(int64_t, CStream::TSeekOrigin) override;
    uint64_t getTotalBytesCount() const override { return 0; }  // unknown for gz; nobody asks
    /** Bytes of the uncompressed stream consumed so far (pushed-back bytes are not consumed). */
    uint64_t getPosition() const override { return consumed_; }
    /** The next Read()s return these bytes first. */
    void pushBack(const std::vector<std::uint8_t>& bytes);
    /** zlib reported corrupt data: every later Read() returns 0 bytes. */
    bool corrupt() const { return corrupt_; }

   private:
    mrpt::io::CFileGZInputStream& in_;
    std::vector<std::uint8_t> pending_;  // pushed back, in order
    size_t pending_at_ = 0;
    uint64_t consumed_ = 0;
    bool corrupt_ = false;
};

/** Reads the fields of MRPT's archive format (little endian, as MRPT writes on every platform we run on) from a
 *  RawlogStream. `context` names what is being read ("mrpt::obs::CObservationStereoImages > imageLeft"); the
 *  errors say "<file>: entry <n> (byte <offset> of the uncompressed stream), <context>: <problem>". */
class FieldReader
{
   public:
    FieldReader(RawlogStream& in, std::string path) : in_(in), path_(std::move(path)) {}

    /** Starts the next top-level object (entry numbers as MRPT's CRawlog counts them: one per object). */
    void startEntry(size_t entry)
    {
        entry_ = entry;
        entry_offset_ = in_.getPosition();
        context_.clear();
    }
    size_t entry() const { return entry_; }
    const std::string& path() const { return path_; }
    RawlogStream& stream() { return in_; }

    /** A fixed-size value (integers, double). Truncation is an error. */
    template <class T>
    T pod(const char* field)
    {
        static_assert(std::is_trivially_copyable_v<T>);
        T value;
        readExactly(&value, sizeof(T), field);
        return value;
    }
    /** A bool stored as one byte: MRPT writes 0 or 1; any other byte reads as true (as normaliseBool did). */
    bool flag(const char* field) { return pod<std::uint8_t>(field) != 0; }
    /** A uint32 length and that many bytes (MRPT's std::string), at most `max_length` bytes. */
    std::string text(const char* field, size_t max_length);
    /** `count` bytes, read in slices as they arrive, so that a length field beyond the end of the file fails as
     *  "truncated" without allocating what it announces. */
    std::vector<std::uint8_t> bytes(size_t count, const char* field);
    /** Reads up to `count` bytes; returns how many arrived (0 at the end of the stream). */
    size_t readSome(void* buffer, size_t count);
    void readExactly(void* buffer, size_t count, const char* field);

    /** InputError naming the file, entry, offset, the context and `problem`. */
    [[noreturn]] void fail(const std::string& problem) const;

    /** Names what is read while it lives: pushes "<name>" onto the context. */
    class Scope
    {
       public:
        Scope(FieldReader& r, const std::string& name) : r_(r), size_(r.context_.size())
        {
            r_.context_ += (size_ ? " > " : "") + name;
        }
        ~Scope() { r_.context_.resize(size_); }
        Scope(const Scope&) = delete;
        Scope& operator=(const Scope&) = delete;

       private:
        FieldReader& r_;
        size_t size_;
    };

   private:
    RawlogStream& in_;
    std::string path_;
    std::string context_;
    size_t entry_ = 0;
    uint64_t entry_offset_ = 0;
};

}  // namespace quasiloc::dataset::detail
