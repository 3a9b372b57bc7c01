// Decoder of GMMLoc's .gmm files (see gmm.h): protobuf wire format read by hand.
#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>
#include <quasiloc/core/error.h>
#include <quasiloc/map/gmm.h>

namespace quasiloc::map
{
namespace
{
/** A cursor over protobuf wire-format bytes; every read checks bounds and throws InputError. */
class WireReader
{
   public:
    WireReader(const uint8_t* begin, const uint8_t* end, const std::string& input) : p_(begin), end_(end), input_(input)
    {}
    bool done() const { return p_ >= end_; }
    size_t offset(const uint8_t* base) const { return static_cast<size_t>(p_ - base); }

    uint64_t varint()
    {
        uint64_t value = 0;
        for (int shift = 0; shift < 64; shift += 7)
        {
            need(1);
            const uint8_t byte = *p_++;
            value |= static_cast<uint64_t>(byte & 0x7f) << shift;
            if ((byte & 0x80) == 0) return value;
        }
        throw core::InputError(input_, "malformed protobuf varint (more than 10 bytes)");
    }
    double fixed64Double()
    {
        need(8);
        uint64_t bits = 0;
        for (int i = 0; i < 8; ++i) bits |= static_cast<uint64_t>(p_[i]) << (8 * i);  // little endian
        p_ += 8;
        double d;
        std::memcpy(&d, &bits, sizeof d);
        return d;
    }
    /** A length-delimited payload as a sub-reader. */
    WireReader sub()
    {
        const uint64_t len = varint();
        need(len);
        WireReader r(p_, p_ + len, input_);
        p_ += len;
        return r;
    }
    void skip(uint32_t wire_type)
    {
        switch (wire_type)
        {
            case 0: varint(); break;
            case 1:
                need(8);
                p_ += 8;
                break;
            case 2: sub(); break;
            case 5:
                need(4);
                p_ += 4;
                break;
            default: throw core::InputError(input_, "unsupported protobuf wire type " + std::to_string(wire_type));
        }
    }

   private:
    void need(uint64_t n) const
    {
        if (static_cast<uint64_t>(end_ - p_) < n) throw core::InputError(input_, "truncated protobuf data");
    }
    const uint8_t* p_;
    const uint8_t* end_;
    std::string input_;
};

/** Repeated double field: packed (wire type 2) or one element per tag (wire type 1). */
void readDoubles(WireReader& r, uint32_t wire_type, std::vector<double>& out, const std::string& input)
{
    if (wire_type == 1)
        out.push_back(r.fixed64Double());
    else if (wire_type == 2)
    {
        WireReader packed = r.sub();
        while (!packed.done()) out.push_back(packed.fixed64Double());
    }
    else
        throw core::InputError(input, "repeated double field with wire type " + std::to_string(wire_type));
}

GmmComponent decodeComponent(WireReader r, const std::string& input)
{
    GmmComponent c;
    std::vector<double> mean, cov;
    while (!r.done())
    {
        const uint64_t key = r.varint();
        const auto field = static_cast<uint32_t>(key >> 3), wire_type = static_cast<uint32_t>(key & 7);
        if ((field == 1 || field == 2) && wire_type == 0)
            (field == 1 ? c.is_degenerated : c.is_salient) = r.varint() != 0;
        else if (field == 3)
            readDoubles(r, wire_type, mean, input);
        else if (field == 4)
            readDoubles(r, wire_type, cov, input);
        else
            r.skip(wire_type);
    }
    core::require(mean.size() == 3 && cov.size() == 9, input,
                  "component with " + std::to_string(mean.size()) + " means and " + std::to_string(cov.size()) +
                      " covariance values (expected 3 and 9)");
    for (int i = 0; i < 3; ++i) c.mean[i] = mean[i];
    for (int i = 0; i < 9; ++i) c.covariance(i / 3, i % 3) = cov[i];
    core::require(c.mean.allFinite() && c.covariance.allFinite(), input, "non-finite mean or covariance");
    return c;
}
}  // namespace

std::vector<GmmComponent> decodeGmm(const std::vector<uint8_t>& bytes, const std::string& input)
{
    const uint8_t* base = bytes.data();
    WireReader r(base, base + bytes.size(), input);
    core::require(!r.done(), input, "empty GMM file");
    const uint64_t count = r.varint();
    std::vector<GmmComponent> comps;
    // Not `count`: it is not trusted yet. A component takes at least 2 bytes (length and a tag).
    comps.reserve(static_cast<size_t>(std::min<uint64_t>(count, bytes.size() / 2)));
    while (!r.done())
    {
        const std::string where = input + " (component " + std::to_string(comps.size()) + ")";
        comps.push_back(decodeComponent(r.sub(), where));
    }
    core::require(
        comps.size() == count, input,
        "header announces " + std::to_string(count) + " components, file holds " + std::to_string(comps.size()));
    return comps;
}

std::vector<GmmComponent> readGmmFile(const std::string& path)
{
    std::ifstream f(path, std::ios::binary);
    core::require(f.good(), path, "cannot open GMM file");
    std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    return decodeGmm(bytes, path);
}

}  // namespace quasiloc::map
