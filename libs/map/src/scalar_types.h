#pragma once
// Internal: the numeric types of PLY/PCD fields and how to decode one stored value. Shared by the
// PLY and PCD readers and by the test writers (which encode the same types).
#include <cstdint>
#include <cstring>
#include <quasiloc/map/point_records.h>
#include <string>

namespace quasiloc::map::detail
{
/** The type itself is public (point_records.h): PointCloud2 decoding names its fields' types with it. */
using ScalarType = quasiloc::map::ScalarType;

inline size_t sizeOf(ScalarType t)
{
    switch (t)
    {
        case ScalarType::Int8:
        case ScalarType::UInt8: return 1;
        case ScalarType::Int16:
        case ScalarType::UInt16: return 2;
        case ScalarType::Int32:
        case ScalarType::UInt32:
        case ScalarType::Float32: return 4;
        case ScalarType::Int64:
        case ScalarType::UInt64:
        case ScalarType::Float64: return 8;
    }
    return 0;
}

inline bool hostIsBigEndian()
{
    const uint16_t one = 1;
    uint8_t first;
    std::memcpy(&first, &one, 1);
    return first == 0;
}

/** Decodes one value stored at `p` (unaligned) with the given byte order. */
inline double decodeScalar(const uint8_t* p, ScalarType t, bool swap_bytes)
{
    uint8_t buf[8];
    const size_t n = sizeOf(t);
    if (swap_bytes)
        for (size_t k = 0; k < n; ++k) buf[k] = p[n - 1 - k];
    else
        std::memcpy(buf, p, n);
    switch (t)
    {
        case ScalarType::Int8: return static_cast<int8_t>(buf[0]);
        case ScalarType::UInt8: return buf[0];
#define QUASILOC_DECODE(T)               \
    {                                    \
        T v;                             \
        std::memcpy(&v, buf, sizeof(T)); \
        return static_cast<double>(v);   \
    }
        case ScalarType::Int16: QUASILOC_DECODE(int16_t)
        case ScalarType::UInt16: QUASILOC_DECODE(uint16_t)
        case ScalarType::Int32: QUASILOC_DECODE(int32_t)
        case ScalarType::UInt32: QUASILOC_DECODE(uint32_t)
        case ScalarType::Int64: QUASILOC_DECODE(int64_t)
        case ScalarType::UInt64: QUASILOC_DECODE(uint64_t)
        case ScalarType::Float32: QUASILOC_DECODE(float)
        case ScalarType::Float64: QUASILOC_DECODE(double)
#undef QUASILOC_DECODE
    }
    return 0;
}

/** Encodes `v` (converted to the type) at `p` with the given byte order (used by writers). */
inline void encodeScalar(double v, ScalarType t, bool swap_bytes, uint8_t* p)
{
    uint8_t buf[8];
    switch (t)
    {
#define QUASILOC_ENCODE(T)               \
    {                                    \
        const T x = static_cast<T>(v);   \
        std::memcpy(buf, &x, sizeof(T)); \
        break;                           \
    }
        case ScalarType::Int8: QUASILOC_ENCODE(int8_t)
        case ScalarType::UInt8: QUASILOC_ENCODE(uint8_t)
        case ScalarType::Int16: QUASILOC_ENCODE(int16_t)
        case ScalarType::UInt16: QUASILOC_ENCODE(uint16_t)
        case ScalarType::Int32: QUASILOC_ENCODE(int32_t)
        case ScalarType::UInt32: QUASILOC_ENCODE(uint32_t)
        case ScalarType::Int64: QUASILOC_ENCODE(int64_t)
        case ScalarType::UInt64: QUASILOC_ENCODE(uint64_t)
        case ScalarType::Float32: QUASILOC_ENCODE(float)
        case ScalarType::Float64: QUASILOC_ENCODE(double)
#undef QUASILOC_ENCODE
    }
    const size_t n = sizeOf(t);
    if (swap_bytes)
        for (size_t k = 0; k < n; ++k) p[k] = buf[n - 1 - k];
    else
        std::memcpy(p, buf, n);
}

/** PLY type names: char uchar short ushort int uint float double and int8 uint8 int16 uint16 int32
 *  uint32 float32 float64. Returns false for an unknown name. */
inline bool plyTypeFromName(const std::string& name, ScalarType& t)
{
    static const struct
    {
        const char* name;
        ScalarType type;
    } table[] = {{"char", ScalarType::Int8},      {"int8", ScalarType::Int8},       {"uchar", ScalarType::UInt8},
                 {"uint8", ScalarType::UInt8},    {"short", ScalarType::Int16},     {"int16", ScalarType::Int16},
                 {"ushort", ScalarType::UInt16},  {"uint16", ScalarType::UInt16},   {"int", ScalarType::Int32},
                 {"int32", ScalarType::Int32},    {"uint", ScalarType::UInt32},     {"uint32", ScalarType::UInt32},
                 {"float", ScalarType::Float32},  {"float32", ScalarType::Float32}, {"double", ScalarType::Float64},
                 {"float64", ScalarType::Float64}};
    for (const auto& e : table)
        if (name == e.name)
        {
            t = e.type;
            return true;
        }
    return false;
}

/** PCD TYPE (I, U, F) + SIZE (1, 2, 4, 8) -> type. Returns false for an invalid combination. */
inline bool pcdType(char type, int size, ScalarType& t)
{
    if (type == 'I' && size == 1)
        t = ScalarType::Int8;
    else if (type == 'I' && size == 2)
        t = ScalarType::Int16;
    else if (type == 'I' && size == 4)
        t = ScalarType::Int32;
    else if (type == 'I' && size == 8)
        t = ScalarType::Int64;
    else if (type == 'U' && size == 1)
        t = ScalarType::UInt8;
    else if (type == 'U' && size == 2)
        t = ScalarType::UInt16;
    else if (type == 'U' && size == 4)
        t = ScalarType::UInt32;
    else if (type == 'U' && size == 8)
        t = ScalarType::UInt64;
    else if (type == 'F' && size == 4)
        t = ScalarType::Float32;
    else if (type == 'F' && size == 8)
        t = ScalarType::Float64;
    else
        return false;
    return true;
}

}  // namespace quasiloc::map::detail
