#include <algorithm>
#include <cstring>
#include <quasiloc/map/lzf.h>

namespace quasiloc::map
{
namespace
{
constexpr size_t kMaxLiteral = 32;   // a literal run is 1..32 bytes
constexpr size_t kMaxOffset = 8192;  // 13-bit offset (+1)
constexpr size_t kMaxMatch = 7 + 255 + 2;
constexpr int kHashBits = 15;

uint32_t hash3(const uint8_t* p)
{
    const uint32_t v = (uint32_t(p[0]) << 16) | (uint32_t(p[1]) << 8) | p[2];
    return (v * 2654435761u) >> (32 - kHashBits);
}

/** Appends the pending literal run [lit_begin, lit_begin + n) to out. */
void flushLiterals(const uint8_t* lit_begin, size_t n, std::vector<uint8_t>& out)
{
    while (n > 0)
    {
        const size_t run = n < kMaxLiteral ? n : kMaxLiteral;
        out.push_back(static_cast<uint8_t>(run - 1));
        out.insert(out.end(), lit_begin, lit_begin + run);
        lit_begin += run;
        n -= run;
    }
}
}  // namespace

std::vector<uint8_t> lzfCompress(const uint8_t* data, size_t size)
{
    std::vector<uint8_t> out;
    out.reserve(size + size / kMaxLiteral + 16);
    // Positions + 1 (0 = empty) of the last occurrence of each 3-byte hash.
    std::vector<size_t> table(size_t(1) << kHashBits, 0);
    size_t ip = 0, lit_begin = 0;
    while (ip + 2 < size)
    {
        const uint32_t h = hash3(data + ip);
        const size_t cand = table[h];
        table[h] = ip + 1;
        if (cand > 0)
        {
            const size_t ref = cand - 1;
            const size_t off = ip - ref - 1;
            if (off < kMaxOffset && std::memcmp(data + ref, data + ip, 3) == 0)
            {
                const size_t max_len = std::min(kMaxMatch, size - ip);
                size_t len = 3;
                while (len < max_len && data[ref + len] == data[ip + len]) ++len;
                flushLiterals(data + lit_begin, ip - lit_begin, out);
                const size_t l = len - 2;
                if (l < 7)
                    out.push_back(static_cast<uint8_t>((l << 5) | (off >> 8)));
                else
                {
                    out.push_back(static_cast<uint8_t>((7 << 5) | (off >> 8)));
                    out.push_back(static_cast<uint8_t>(l - 7));
                }
                out.push_back(static_cast<uint8_t>(off & 0xff));
                ip += len;
                lit_begin = ip;
                continue;
            }
        }
        ++ip;
    }
    flushLiterals(data + lit_begin, size - lit_begin, out);
    return out;
}

std::optional<size_t> lzfDecompress(const uint8_t* in, size_t in_size, uint8_t* out, size_t out_capacity)
{
    size_t ip = 0, op = 0;
    while (ip < in_size)
    {
        const size_t ctrl = in[ip++];
        if (ctrl < 32)
        {
            const size_t run = ctrl + 1;
            if (ip + run > in_size || op + run > out_capacity) return std::nullopt;
            std::memcpy(out + op, in + ip, run);
            ip += run;
            op += run;
            continue;
        }
        size_t len = ctrl >> 5;
        if (len == 7)
        {
            if (ip >= in_size) return std::nullopt;
            len += in[ip++];
        }
        if (ip >= in_size) return std::nullopt;
        const size_t back = ((ctrl & 0x1f) << 8) + in[ip++] + 1;
        len += 2;
        if (back > op || op + len > out_capacity) return std::nullopt;
        // Byte by byte: the source may overlap the destination (run-length style references).
        const uint8_t* src = out + op - back;
        for (size_t k = 0; k < len; ++k) out[op + k] = src[k];
        op += len;
    }
    return op;
}

}  // namespace quasiloc::map
