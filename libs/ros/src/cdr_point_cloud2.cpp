// The CDR layout of sensor_msgs/PointCloud2 and sensor_msgs/PointField (point_cloud2.h), field by field as their .msg
// definitions declare them, listed once and walked by a decoding or an encoding visitor (as cdr_messages.cpp does for
// the other types).
#include <quasiloc/ros/point_cloud2.h>

namespace quasiloc::ros::cdr
{
namespace
{
struct Decode
{
    Reader& r;
    void operator()(MsgHeader& h) { h = readHeader(r); }
    void operator()(std::uint8_t& v) { v = r.u8(); }
    void operator()(bool& v) { v = r.boolean(); }
    void operator()(std::uint32_t& v) { v = r.u32(); }
    void operator()(std::string& v) { v = r.string(); }
    void operator()(std::vector<std::uint8_t>& v) { v = r.byteSequence(); }
    template <class F>
    void sequence(std::vector<PointFieldMsg>& v, std::size_t min_element_bytes, F&& element)
    {
        v.resize(r.sequenceLength(min_element_bytes));
        for (auto& e : v) element(e);
    }
};

struct Encode
{
    Writer& w;
    void operator()(const MsgHeader& h) { writeHeader(w, h); }
    void operator()(std::uint8_t v) { w.u8(v); }
    void operator()(bool v) { w.boolean(v); }
    void operator()(std::uint32_t v) { w.u32(v); }
    void operator()(const std::string& v) { w.string(v); }
    void operator()(const std::vector<std::uint8_t>& v) { w.byteSequence(v); }
    template <class F>
    void sequence(const std::vector<PointFieldMsg>& v, std::size_t, F&& element)
    {
        w.u32(std::uint32_t(v.size()));
        for (const auto& e : v) element(e);
    }
};

template <class IO, class F>
void pointFieldFields(IO& io, F& f)
{
    io(f.name);
    io(f.offset);
    io(f.datatype);
    io(f.count);
}

template <class IO, class M>
void pointCloud2Fields(IO& io, M& m)
{
    io(m.header);
    io(m.height);
    io(m.width);
    // A PointField takes at least 4 (name length) + 4 + 1 + 3 (padding) + 4 bytes.
    io.sequence(m.fields, 16, [&](auto& f) { pointFieldFields(io, f); });
    io(m.is_bigendian);
    io(m.point_step);
    io(m.row_step);
    io(m.data);
    io(m.is_dense);
}
}  // namespace

PointCloud2Msg readPointCloud2(Reader& r)
{
    PointCloud2Msg m;
    Decode d{r};
    pointCloud2Fields(d, m);
    return m;
}

std::vector<std::uint8_t> encode(const PointCloud2Msg& m)
{
    Writer w;
    Encode e{w};
    pointCloud2Fields(e, m);
    return w.take();
}

}  // namespace quasiloc::ros::cdr
