#pragma once
// Flat binary I/O of OpenCV matrices and plain-data vectors through an MRPT archive (the database file).
// Reads check sizes against a sanity limit so a corrupt file gives an error instead of a huge allocation.
#include <mrpt/serialization/CArchive.h>

#include <cstdint>
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

inline cv::Mat readMat(mrpt::serialization::CArchive& in)
{
    const int32_t rows = in.ReadAs<int32_t>(), cols = in.ReadAs<int32_t>(), type = in.ReadAs<int32_t>();
    if (rows < 0 || cols < 0 || uint64_t(rows) * uint64_t(cols) > kMaxElements || (type & ~0xFFF) != 0)
        throw std::runtime_error("corrupt matrix header (" + std::to_string(rows) + "x" + std::to_string(cols) + ")");
    cv::Mat m(rows, cols, type);
    if (!m.empty() && in.ReadBuffer(m.data, m.total() * m.elemSize()) != m.total() * m.elemSize())
        throw std::runtime_error("truncated matrix data");
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
    static_assert(std::is_standard_layout_v<T>, "flat plain data only (memcpy)");
    const uint64_t n = in.ReadAs<uint64_t>();
    if (n > kMaxElements / sizeof(T)) throw std::runtime_error("corrupt vector length " + std::to_string(n));
    std::vector<T> v(n);
    if (n && in.ReadBuffer(v.data(), n * sizeof(T)) != n * sizeof(T)) throw std::runtime_error("truncated array data");
    return v;
}

}  // namespace quasiloc::reloc::detail
