// The CDR layouts of the ROS 2 messages bag2rawlog reads and rawlog2bag writes (cdr.h), field by field as their
// .msg definitions declare them (builtin_interfaces/Time is int32 sec + uint32 nanosec).
#include <quasiloc/core/error.h>
#include <quasiloc/ros/cdr.h>

namespace quasiloc::ros
{
std::string normalisedTypeName(const std::string& type)
{
    const auto first = type.find('/');
    if (first == std::string::npos) return type;
    const auto second = type.find('/', first + 1);
    if (second == std::string::npos) return type;
    const std::string middle = type.substr(first + 1, second - first - 1);
    if (middle != "msg") return type;
    return type.substr(0, first) + type.substr(second);
}
}  // namespace quasiloc::ros

namespace quasiloc::ros::cdr
{
namespace
{
// Each message's fields are listed once (the *Fields functions), in declaration order, and walked by a Decode or an
// Encode visitor: the reader and the writer of a type cannot disagree on its layout.

/** Reads each field it is given. */
struct Decode
{
    Reader& r;
    void operator()(bool& v) { v = r.boolean(); }
    void operator()(std::uint32_t& v) { v = r.u32(); }
    void operator()(double& v) { v = r.f64(); }
    void operator()(std::string& v) { v = r.string(); }
    void operator()(std::vector<std::uint8_t>& v) { v = r.byteSequence(); }
    void operator()(std::vector<double>& v) { v = r.f64Sequence(); }
    template <std::size_t N>
    void operator()(std::array<double, N>& a)
    {
        r.f64Array(a);
    }
    void operator()(Eigen::Vector3d& v)
    {
        for (int i = 0; i < 3; ++i) v[i] = r.f64();
    }
    /** geometry_msgs/Quaternion: x y z w. */
    void operator()(Eigen::Quaterniond& q)
    {
        const double x = r.f64(), y = r.f64(), z = r.f64(), w = r.f64();
        q = Eigen::Quaterniond(w, x, y, z);
    }
    void operator()(MsgHeader& h) { h = readHeader(r); }
    /** Fields we do not keep (binning, region of interest): read past. */
    void unusedU32() { r.u32(); }
    void unusedBool() { r.boolean(); }
};

/** Writes each field it is given. */
struct Encode
{
    Writer& w;
    void operator()(bool v) { w.boolean(v); }
    void operator()(std::uint32_t v) { w.u32(v); }
    void operator()(double v) { w.f64(v); }
    void operator()(const std::string& v) { w.string(v); }
    void operator()(const std::vector<std::uint8_t>& v) { w.byteSequence(v); }
    void operator()(const std::vector<double>& v) { w.f64Sequence(v); }
    template <std::size_t N>
    void operator()(const std::array<double, N>& a)
    {
        w.f64Array(a);
    }
    void operator()(const Eigen::Vector3d& v)
    {
        for (int i = 0; i < 3; ++i) w.f64(v[i]);
    }
    void operator()(const Eigen::Quaterniond& q)
    {
        for (double v : {q.x(), q.y(), q.z(), q.w()}) w.f64(v);
    }
    void operator()(const MsgHeader& h) { writeHeader(w, h); }
    void unusedU32() { w.u32(0); }
    void unusedBool() { w.boolean(false); }
};

template <class IO, class M>
void imageFields(IO& io, M& m)
{
    io(m.header);
    io(m.height);
    io(m.width);
    io(m.encoding);
    io(m.is_bigendian);
    io(m.step);
    io(m.data);
}

template <class IO, class M>
void compressedImageFields(IO& io, M& m)
{
    io(m.header);
    io(m.format);
    io(m.data);
}

template <class IO, class M>
void imuFields(IO& io, M& m)
{
    io(m.header);
    io(m.orientation);
    io(m.orientation_covariance);
    io(m.angular_velocity);
    io(m.angular_velocity_covariance);
    io(m.linear_acceleration);
    io(m.linear_acceleration_covariance);
}

template <class IO, class M>
void cameraInfoFields(IO& io, M& m)
{
    io(m.header);
    io(m.height);
    io(m.width);
    io(m.distortion_model);
    io(m.d);
    io(m.k);
    io(m.r);
    io(m.p);
    for (int i = 0; i < 2 + 4; ++i) io.unusedU32();  // binning_x, binning_y, roi x_offset, y_offset, height, width
    io.unusedBool();                                 // roi do_rectify
}

/** geometry_msgs/PoseStamped (header, Point position, Quaternion orientation). */
template <class IO, class M>
void poseStampedFields(IO& io, M& m)
{
    io(m.header);
    io(m.position);
    io(m.orientation);
}

template <class IO, class M>
void transformStampedFields(IO& io, M& m)
{
    io(m.header);
    io(m.child_frame_id);
    io(m.translation);
    io(m.rotation);
}
}  // namespace

MsgHeader readHeader(Reader& r)
{
    MsgHeader h;
    const std::int32_t sec = r.i32();
    const std::uint32_t nanosec = r.u32();
    if (nanosec >= 1000000000u)
        throw core::InputError(r.where(), "header stamp with nanosec " + std::to_string(nanosec) + " >= 1e9");
    h.stamp_ns = std::int64_t(sec) * 1000000000 + nanosec;
    h.frame_id = r.string();
    return h;
}

void writeHeader(Writer& w, const MsgHeader& h)
{
    const std::int64_t sec = h.stamp_ns >= 0 ? h.stamp_ns / 1000000000 : (h.stamp_ns - 999999999) / 1000000000;
    w.i32(std::int32_t(sec));
    w.u32(std::uint32_t(h.stamp_ns - sec * 1000000000));
    w.string(h.frame_id);
}

template <class M, void (*Fields)(Decode&, M&)>
M decodeWith(Reader& r)
{
    M m;
    Decode d{r};
    Fields(d, m);
    return m;
}

ImageMsg readImage(Reader& r) { return decodeWith<ImageMsg, imageFields<Decode, ImageMsg>>(r); }
CompressedImageMsg readCompressedImage(Reader& r)
{
    return decodeWith<CompressedImageMsg, compressedImageFields<Decode, CompressedImageMsg>>(r);
}
ImuMsg readImu(Reader& r) { return decodeWith<ImuMsg, imuFields<Decode, ImuMsg>>(r); }
CameraInfoMsg readCameraInfo(Reader& r)
{
    return decodeWith<CameraInfoMsg, cameraInfoFields<Decode, CameraInfoMsg>>(r);
}
PoseMsg readPoseStamped(Reader& r) { return decodeWith<PoseMsg, poseStampedFields<Decode, PoseMsg>>(r); }
TransformMsg readTransformStamped(Reader& r)
{
    return decodeWith<TransformMsg, transformStampedFields<Decode, TransformMsg>>(r);
}

PoseMsg readOdometry(Reader& r)
{
    // nav_msgs/Odometry: header, child_frame_id, PoseWithCovariance (pose, float64[36]), then the twist (not needed).
    PoseMsg m;
    std::string child_frame_id;
    std::array<double, 36> covariance;
    Decode d{r};
    d(m.header);
    d(child_frame_id);
    d(m.position);
    d(m.orientation);
    d(covariance);
    return m;
}

std::vector<TransformMsg> readTFMessage(Reader& r)
{
    // A TransformStamped takes at least 4 + 4 + 4 + 4 + 7 x 8 bytes.
    const std::uint32_t n = r.sequenceLength(72);
    std::vector<TransformMsg> v;
    v.reserve(n);
    for (std::uint32_t i = 0; i < n; ++i) v.push_back(readTransformStamped(r));
    return v;
}

template <class M, void (*Fields)(Encode&, const M&)>
std::vector<std::uint8_t> encodeWith(const M& m)
{
    Writer w;
    Encode e{w};
    Fields(e, m);
    return w.take();
}

std::vector<std::uint8_t> encode(const ImageMsg& m)
{
    return encodeWith<ImageMsg, imageFields<Encode, const ImageMsg>>(m);
}
std::vector<std::uint8_t> encode(const CompressedImageMsg& m)
{
    return encodeWith<CompressedImageMsg, compressedImageFields<Encode, const CompressedImageMsg>>(m);
}
std::vector<std::uint8_t> encode(const ImuMsg& m) { return encodeWith<ImuMsg, imuFields<Encode, const ImuMsg>>(m); }
std::vector<std::uint8_t> encode(const CameraInfoMsg& m)
{
    return encodeWith<CameraInfoMsg, cameraInfoFields<Encode, const CameraInfoMsg>>(m);
}
std::vector<std::uint8_t> encode(const PoseMsg& m)
{
    return encodeWith<PoseMsg, poseStampedFields<Encode, const PoseMsg>>(m);
}

std::vector<std::uint8_t> encodeTFMessage(const std::vector<TransformMsg>& transforms)
{
    Writer w;
    Encode e{w};
    w.u32(std::uint32_t(transforms.size()));
    for (const auto& t : transforms) transformStampedFields(e, t);
    return w.take();
}

}  // namespace quasiloc::ros::cdr
