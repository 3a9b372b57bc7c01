#pragma once
// Flat binary I/O of OpenCV matrices and plain-data vectors through an MRPT archive (the database file).
// Reads check sizes against a sanity limit and allocate as the data arrives, so that a corrupt length field gives an
// error instead of a huge allocation.
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace quasiloc::reloc::detail
{
constexpr uint64_t kMaxElements = uint64_t(1) << 34;

inline void writeMat(mrpt::serialization::CArchive& out, const cv::Mat& m)
{
    const cv::Mat c = m.isContinuous() ? m : m.clone();
    out.WriteAs<int32_t>(c.rows);
    out.WriteAs<int32_t>(c.cols);
    out.WriteAs<int32_t>(c.type());
    if (!c.empty()) out.WriteBuffer(c.data, c.total() * c.elemSize());
}

/** Reads `count` elements in slices of at most 1 MiB, so that memory grows with the data actually present: a corrupt
 *  count ends in an error ("truncated") once the stream runs out, instead of an allocation of what it claims. */
template <typename T>
std::vector<T> readElements(mrpt::serialization::CArchive& in, uint64_t count, const char* what)
{
    static_assert(std::is_standard_layout_v<T>, "flat plain data only (memcpy)");
    constexpr uint64_t kSlice = (uint64_t(1) << 20) / sizeof(T) + 1;
    std::vector<T> v;
    while (v.size() < count)
    {
        const size_t old = v.size(), n = size_t(std::min<uint64_t>(kSlice, count - old));
        v.resize(old + n);
        size_t got = 0;
        if constexpr (std::is_arithmetic_v<T>)
            got = in.ReadBufferFixEndianness(v.data() + old, n);
        else
            got = in.ReadBuffer(v.data() + old, n * sizeof(T));
        if (got != n * sizeof(T)) throw std::runtime_error(std::string("truncated ") + what);
    }
    return v;
}

inline cv::Mat readMat(mrpt::serialization::CArchive& in)
{
    const int32_t rows = in.ReadAs<int32_t>(), cols = in.ReadAs<int32_t>(), type = in.ReadAs<int32_t>();
    if (rows < 0 || cols < 0 || uint64_t(rows) * uint64_t(cols) > kMaxElements || (type & ~0xFFF) != 0)
        throw std::runtime_error("corrupt matrix header (" + std::to_string(rows) + "x" + std::to_string(cols) + ")");
    const uint64_t bytes = uint64_t(rows) * uint64_t(cols) * CV_ELEM_SIZE(type);
    const std::vector<uint8_t> data = readElements<uint8_t>(in, bytes, "matrix data");  // before allocating the Mat
    cv::Mat m(rows, cols, type);
    if (bytes) std::memcpy(m.data, data.data(), bytes);
    return m;
}

template <typename T>
void writeVector(mrpt::serialization::CArchive& out, const std::vector<T>& v)
{
    static_assert(std::is_standard_layout_v<T>, "flat plain data only (memcpy)");
    out.WriteAs<uint64_t>(v.size());
    if (!v.empty()) out.WriteBuffer(v.data(), v.size() * sizeof(T));
}

template <typename T>
std::vector<T> readVector(mrpt::serialization::CArchive& in)
{
    const uint64_t n = in.ReadAs<uint64_t>();
    if (n > kMaxElements / sizeof(T)) throw std::runtime_error("corrupt vector length " + std::to_string(n));
    return readElements<T>(in, n, "array data");
}

/** A string as MRPT's CArchive writes it (uint32 length, then the characters), read without trusting the length
 *  (MRPT's operator>> allocates the announced length first: up to 4 GB). */
inline std::string readString(mrpt::serialization::CArchive& in)
{
    const uint32_t n = in.ReadAs<uint32_t>();
    const std::vector<char> chars = readElements<char>(in, n, "string");
    return std::string(chars.begin(), chars.end());
}

}  // namespace quasiloc::reloc::detail
