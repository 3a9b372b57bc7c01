// CRC-32, zstd and LZ4 frames (compression.h), on zlib, libzstd and liblz4.
#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <fstream>
#include <memory>
#include <quasiloc/core/error.h>
#include <quasiloc/ros/compression.h>

using quasiloc::core::InputError;

namespace quasiloc::ros
{
std::uint32_t crc32Of(const std::uint8_t* data, std::size_t size, std::uint32_t crc)
{
    // zlib takes uInt lengths: feed big buffers in pieces.
    while (size > 0)
    {
        const std::size_t n = std::min<std::size_t>(size, 1u << 30);
        crc = std::uint32_t(::crc32(crc, data, uInt(n)));
        data += n;
        size -= n;
    }
    return crc;
}

namespace
{
/** Grows `out` by at most a step, never beyond max_bytes (+1, to detect an overflow). */
void grow(std::vector<std::uint8_t>& out, std::size_t used, std::size_t max_bytes, const std::string& where)
{
    if (used < out.size()) return;
    if (used > max_bytes)
        throw InputError(where, "decompresses to more than the " + std::to_string(max_bytes) + " bytes declared");
    const std::size_t step = std::max<std::size_t>(64 * 1024, out.size());
    out.resize(std::min(max_bytes + 1, out.size() + step));
}
}  // namespace

std::vector<std::uint8_t> zstdDecompress(const std::uint8_t* data, std::size_t size, std::size_t max_bytes,
                                         const std::string& where)
{
    std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> ctx(ZSTD_createDCtx(), ZSTD_freeDCtx);
    std::vector<std::uint8_t> out;
    ZSTD_inBuffer in{data, size, 0};
    std::size_t used = 0, last = 1;
    while (in.pos < in.size || last != 0)
    {
        grow(out, used, max_bytes, where);
        ZSTD_outBuffer o{out.data(), out.size(), used};
        const std::size_t before_in = in.pos;
        last = ZSTD_decompressStream(ctx.get(), &o, &in);
        if (ZSTD_isError(last)) throw InputError(where, std::string("zstd: ") + ZSTD_getErrorName(last));
        if (o.pos == used && in.pos == before_in && o.pos < o.size)
            throw InputError(where, "zstd: truncated data");  // no progress with room left: input ended mid-frame
        used = o.pos;
        if (used > max_bytes)
            throw InputError(where, "decompresses to more than the " + std::to_string(max_bytes) + " bytes declared");
    }
    out.resize(used);
    return out;
}

std::vector<std::uint8_t> lz4Decompress(const std::uint8_t* data, std::size_t size, std::size_t max_bytes,
                                        const std::string& where)
{
    LZ4F_dctx* raw = nullptr;
    if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION))) throw InputError(where, "lz4: no context");
    std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> ctx(raw, LZ4F_freeDecompressionContext);
    std::vector<std::uint8_t> out;
    std::size_t in_pos = 0, used = 0, hint = 1;
    while (hint != 0)
    {
        if (in_pos >= size) throw InputError(where, "lz4: truncated frame");
        grow(out, used, max_bytes, where);
        std::size_t dst = out.size() - used, src = size - in_pos;
        hint = LZ4F_decompress(ctx.get(), out.data() + used, &dst, data + in_pos, &src, nullptr);
        if (LZ4F_isError(hint)) throw InputError(where, std::string("lz4: ") + LZ4F_getErrorName(hint));
        in_pos += src;
        used += dst;
        if (used > max_bytes)
            throw InputError(where, "decompresses to more than the " + std::to_string(max_bytes) + " bytes declared");
    }
    out.resize(used);
    return out;
}

std::vector<std::uint8_t> zstdCompress(const std::uint8_t* data, std::size_t size, int level)
{
    std::vector<std::uint8_t> out(ZSTD_compressBound(size));
    const std::size_t n = ZSTD_compress(out.data(), out.size(), data, size, level);
    if (ZSTD_isError(n)) throw std::runtime_error(std::string("zstd: ") + ZSTD_getErrorName(n));
    out.resize(n);
    return out;
}

std::vector<std::uint8_t> lz4Compress(const std::uint8_t* data, std::size_t size)
{
    LZ4F_preferences_t prefs{};
    prefs.frameInfo.contentSize = size;
    std::vector<std::uint8_t> out(LZ4F_compressFrameBound(size, &prefs));
    const std::size_t n = LZ4F_compressFrame(out.data(), out.size(), data, size, &prefs);
    if (LZ4F_isError(n)) throw std::runtime_error(std::string("lz4: ") + LZ4F_getErrorName(n));
    out.resize(n);
    return out;
}

void zstdDecompressFile(const std::string& from, const std::string& to)
{
    std::ifstream in(from, std::ios::binary);
    if (!in) throw InputError(from, "cannot open");
    std::ofstream out(to, std::ios::binary);
    if (!out) throw InputError(to, "cannot write the decompressed file");
    std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> ctx(ZSTD_createDCtx(), ZSTD_freeDCtx);
    std::vector<char> ibuf(ZSTD_DStreamInSize()), obuf(ZSTD_DStreamOutSize());
    std::size_t last = 0;
    bool any = false;
    while (in.read(ibuf.data(), std::streamsize(ibuf.size())) || in.gcount() > 0)
    {
        any = true;
        ZSTD_inBuffer input{ibuf.data(), std::size_t(in.gcount()), 0};
        while (input.pos < input.size)
        {
            ZSTD_outBuffer output{obuf.data(), obuf.size(), 0};
            last = ZSTD_decompressStream(ctx.get(), &output, &input);
            if (ZSTD_isError(last)) throw InputError(from, std::string("zstd: ") + ZSTD_getErrorName(last));
            out.write(obuf.data(), std::streamsize(output.pos));
        }
    }
    if (!any || last != 0) throw InputError(from, "zstd: truncated or empty file");
    if (!out) throw InputError(to, "cannot write the decompressed file");
}

}  // namespace quasiloc::ros
