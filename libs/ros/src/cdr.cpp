// CDR reader and writer (cdr.h).
#include <cstring>
#include <quasiloc/core/error.h>
#include <quasiloc/ros/cdr.h>

using quasiloc::core::InputError;

namespace quasiloc::ros::cdr
{
namespace
{
template <typename T>
T byteSwapped(T v)
{
    std::uint8_t b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
    std::memcpy(&v, b, sizeof(T));
    return v;
}
constexpr std::size_t kEncapsulationBytes = 4;
}  // namespace

Reader::Reader(const std::uint8_t* data, std::size_t size, std::string where) : where_(std::move(where))
{
    if (size < kEncapsulationBytes)
        throw InputError(where_, "CDR message of " + std::to_string(size) + " bytes, shorter than its 4-byte header");
    if (data[0] != 0 || data[1] > 1)
        throw InputError(where_, "CDR encapsulation " + std::to_string(data[0]) + " " + std::to_string(data[1]) +
                                     " is not supported (plain CDR, 0 0 big endian or 0 1 little endian; XCDR2 and "
                                     "parameter lists are not)");
    swap_ = (data[1] == 1) != (__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__);
    body_ = data + kEncapsulationBytes;
    size_ = size - kEncapsulationBytes;
}

void Reader::need(std::size_t n, const char* what) const
{
    if (n > size_ - pos_)
        throw InputError(where_, std::string("CDR message ends inside ") + what + " (at byte " +
                                     std::to_string(pos_ + kEncapsulationBytes) + " of " +
                                     std::to_string(size_ + kEncapsulationBytes) + ")");
}

void Reader::align(std::size_t n)
{
    const std::size_t padded = (pos_ + n - 1) / n * n;
    need(padded - pos_, "padding");
    pos_ = padded;
}

template <typename T>
T Reader::primitive()
{
    align(sizeof(T));
    need(sizeof(T), "a field");
    T v;
    std::memcpy(&v, body_ + pos_, sizeof(T));
    pos_ += sizeof(T);
    return swap_ ? byteSwapped(v) : v;
}

float Reader::f32()
{
    const std::uint32_t bits = u32();
    float v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
}

double Reader::f64()
{
    const std::uint64_t bits = u64();
    double v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
}

std::string Reader::string()
{
    const std::uint32_t n = u32();
    need(n, "a string");
    if (n == 0) return {};  // some writers encode an empty string with no NUL
    if (body_[pos_ + n - 1] != 0) throw InputError(where_, "CDR string without its terminating NUL");
    std::string s(reinterpret_cast<const char*>(body_ + pos_), n - 1);
    pos_ += n;
    return s;
}

std::uint32_t Reader::sequenceLength(std::size_t min_element_bytes)
{
    const std::uint32_t n = u32();
    if (min_element_bytes > 0 && n > remaining() / min_element_bytes)
        throw InputError(where_, "CDR sequence of " + std::to_string(n) + " elements, more than the " +
                                     std::to_string(remaining()) + " bytes left can hold");
    return n;
}

std::vector<std::uint8_t> Reader::byteSequence()
{
    const std::uint32_t n = sequenceLength(1);
    std::vector<std::uint8_t> v(body_ + pos_, body_ + pos_ + n);
    pos_ += n;
    return v;
}

std::vector<double> Reader::f64Sequence()
{
    const std::uint32_t n = sequenceLength(8);
    std::vector<double> v(n);
    for (auto& x : v) x = f64();
    return v;
}

Writer::Writer() : bytes_{0x00, 0x01, 0x00, 0x00} {}

void Writer::align(std::size_t n)
{
    const std::size_t pos = bytes_.size() - kEncapsulationBytes;
    bytes_.resize(bytes_.size() + (n - pos % n) % n, 0);
}

template <typename T>
void Writer::primitive(T v)
{
    align(sizeof(T));
    if (__BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__) v = byteSwapped(v);
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
}

void Writer::f64(double v)
{
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof v);
    primitive(bits);
}

void Writer::string(const std::string& s)
{
    u32(std::uint32_t(s.size() + 1));
    bytes_.insert(bytes_.end(), s.begin(), s.end());
    bytes_.push_back(0);
}

void Writer::byteSequence(const std::vector<std::uint8_t>& b)
{
    u32(std::uint32_t(b.size()));
    bytes_.insert(bytes_.end(), b.begin(), b.end());
}

void Writer::f64Sequence(const std::vector<double>& v)
{
    u32(std::uint32_t(v.size()));
    for (double x : v) f64(x);
}

// The primitives the header's inline readers and writers use.
template std::uint8_t Reader::primitive<std::uint8_t>();
template std::uint16_t Reader::primitive<std::uint16_t>();
template std::uint32_t Reader::primitive<std::uint32_t>();
template std::uint64_t Reader::primitive<std::uint64_t>();
template void Writer::primitive<std::uint8_t>(std::uint8_t);
template void Writer::primitive<std::uint32_t>(std::uint32_t);
template void Writer::primitive<std::uint64_t>(std::uint64_t);

}  // namespace quasiloc::ros::cdr
