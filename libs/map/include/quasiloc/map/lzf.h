#pragma once
// LZF (the byte-oriented LZ77 variant of liblzf, used by PCD "binary_compressed"): our own small
// decompressor and a simple greedy compressor whose output any LZF decompressor accepts.
//
// Stream format: a control byte c. c < 32: a literal run of c + 1 bytes follows. Otherwise a back
// reference: length L = c >> 5 (if L == 7 the next byte is added), offset = ((c & 31) << 8 | next byte);
// copy L + 2 bytes starting offset + 1 bytes before the current output position (may overlap).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace quasiloc::map
{
/** The largest output per input byte: a 3-byte back reference (control, length, offset) copies at most 7 + 255 + 2
 *  = 264 bytes. A reader checks an announced uncompressed size against this before allocating it. */
constexpr size_t kLzfMaxExpansion = 88;

/** Compresses `size` bytes (never fails; incompressible data grows by ~1/32). */
std::vector<uint8_t> lzfCompress(const uint8_t* data, size_t size);

/** Decompresses into out[0, out_capacity). Returns the number of bytes written, or nullopt if the
 *  stream is corrupt (reference before the start, run past the end of the input) or does not fit. */
std::optional<size_t> lzfDecompress(const uint8_t* in, size_t in_size, uint8_t* out, size_t out_capacity);

}  // namespace quasiloc::map
