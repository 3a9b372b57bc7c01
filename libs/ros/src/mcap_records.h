#pragma once
// MCAP record opcodes and a bounds-checked little-endian cursor over a record's content (mcap_reader.cpp,
// mcap_writer.cpp). Field layouts: https://mcap.dev/spec.
#include <cstdint>
#include <cstring>
#include <quasiloc/core/error.h>
#include <string>

namespace quasiloc::ros::mcap
{
namespace op
{
constexpr std::uint8_t kHeader = 0x01, kFooter = 0x02, kSchema = 0x03, kChannel = 0x04, kMessage = 0x05, kChunk = 0x06,
                       kMessageIndex = 0x07, kChunkIndex = 0x08, kStatistics = 0x0B, kSummaryOffset = 0x0E,
                       kDataEnd = 0x0F;
}
constexpr std::size_t kRecordHeaderBytes = 9;  ///< opcode u8 + content length u64
constexpr std::size_t kFooterContentBytes = 20;

class Cursor
{
   public:
    Cursor(const std::uint8_t* p, std::size_t n, std::string where) : p_(p), n_(n), where_(std::move(where)) {}
    std::uint8_t u8() { return std::uint8_t(le(1)); }
    std::uint16_t u16() { return std::uint16_t(le(2)); }
    std::uint32_t u32() { return std::uint32_t(le(4)); }
    std::uint64_t u64() { return le(8); }
    std::string string()
    {
        const auto* p = reinterpret_cast<const char*>(bytes(u32()));
        return std::string(p, n_last_);
    }
    /** A length-prefixed (u32 or u64) byte field: returns its start; its length in lastSize(). */
    const std::uint8_t* bytes32() { return bytes(u32()); }
    const std::uint8_t* bytes64() { return bytes(u64()); }
    /** The rest of the record. */
    const std::uint8_t* rest()
    {
        n_last_ = n_ - pos_;
        const std::uint8_t* r = p_ + pos_;
        pos_ = n_;
        return r;
    }
    std::size_t lastSize() const { return n_last_; }
    std::size_t remaining() const { return n_ - pos_; }

   private:
    void need(std::uint64_t k) const
    {
        if (k > n_ - pos_)
            throw core::InputError(where_, "record ends inside a field (needs " + std::to_string(k) + " bytes, " +
                                               std::to_string(n_ - pos_) + " left)");
    }
    std::uint64_t le(int k)
    {
        need(std::uint64_t(k));
        std::uint64_t v = 0;
        for (int i = k - 1; i >= 0; --i) v = (v << 8) | p_[pos_ + std::size_t(i)];
        pos_ += std::size_t(k);
        return v;
    }
    const std::uint8_t* bytes(std::uint64_t k)
    {
        need(k);
        const std::uint8_t* r = p_ + pos_;
        pos_ += std::size_t(k);
        n_last_ = std::size_t(k);
        return r;
    }

    const std::uint8_t* p_;
    std::size_t n_, pos_ = 0, n_last_ = 0;
    std::string where_;
};

}  // namespace quasiloc::ros::mcap
