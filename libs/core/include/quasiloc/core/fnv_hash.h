#pragma once
// FNV-1a, 64 bits, byte by byte: the identity hashes of map files and map points that output files carry, so that a
// file made for another map is refused (reloc's database shards and place files).
#include <cstddef>
#include <cstdint>

namespace quasiloc::core
{
constexpr uint64_t kFnv1aSeed = 0xcbf29ce484222325ULL;

/** h extended by `bytes` bytes at `data` (start from kFnv1aSeed). */
inline uint64_t fnv1a(uint64_t h, const void* data, size_t bytes)
{
    const auto* p = static_cast<const uint8_t*>(data);
    for (size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 0x100000001b3ULL;
    return h;
}

}  // namespace quasiloc::core
