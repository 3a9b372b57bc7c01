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
Eigen::Vector3d readVector3(Reader& r)
{
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i) v[i] = r.f64();
    return v;
}

/** geometry_msgs/Quaternion: x y z w. */
Eigen::Quaterniond readQuaternion(Reader& r)
{
    const double x = r.f64(), y = r.f64(), z = r.f64(), w = r.f64();
    return Eigen::Quaterniond(w, x, y, z);
}

void writeVector3(Writer& w, const Eigen::Vector3d& v)
{
    for (int i = 0; i < 3; ++i) w.f64(v[i]);
}

void writeQuaternion(Writer& w, const Eigen::Quaterniond& q)
{
    w.f64(q.x());
    w.f64(q.y());
    w.f64(q.z());
    w.f64(q.w());
}

void writeHeader(Writer& w, const MsgHeader& h)
{
    const std::int64_t sec = h.stamp_ns >= 0 ? h.stamp_ns / 1000000000 : (h.stamp_ns - 999999999) / 1000000000;
    w.i32(std::int32_t(sec));
    w.u32(std::uint32_t(h.stamp_ns - sec * 1000000000));
    w.string(h.frame_id);
}

TransformMsg readTransformBody(Reader& r)
{
    TransformMsg m;
    m.header = readHeader(r);
    m.child_frame_id = r.string();
    m.translation = readVector3(r);
    m.rotation = readQuaternion(r);
    return m;
}

void writeTransform(Writer& w, const TransformMsg& t)
{
    writeHeader(w, t.header);
    w.string(t.child_frame_id);
    writeVector3(w, t.translation);
    writeQuaternion(w, t.rotation);
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

ImageMsg readImage(Reader& r)
{
    ImageMsg m;
    m.header = readHeader(r);
    m.height = r.u32();
    m.width = r.u32();
    m.encoding = r.string();
    m.is_bigendian = r.u8() != 0;
    m.step = r.u32();
    m.data = r.byteSequence();
    return m;
}

CompressedImageMsg readCompressedImage(Reader& r)
{
    CompressedImageMsg m;
    m.header = readHeader(r);
    m.format = r.string();
    m.data = r.byteSequence();
    return m;
}

ImuMsg readImu(Reader& r)
{
    ImuMsg m;
    m.header = readHeader(r);
    m.orientation = readQuaternion(r);
    r.f64Array(m.orientation_covariance);
    m.angular_velocity = readVector3(r);
    r.f64Array(m.angular_velocity_covariance);
    m.linear_acceleration = readVector3(r);
    r.f64Array(m.linear_acceleration_covariance);
    return m;
}

CameraInfoMsg readCameraInfo(Reader& r)
{
    CameraInfoMsg m;
    m.header = readHeader(r);
    m.height = r.u32();
    m.width = r.u32();
    m.distortion_model = r.string();
    m.d = r.f64Sequence();
    r.f64Array(m.k);
    r.f64Array(m.r);
    r.f64Array(m.p);
    for (int i = 0; i < 2 + 4; ++i) r.u32();  // binning_x, binning_y, roi x_offset, y_offset, height, width
    r.boolean();                              // roi do_rectify
    return m;
}

PoseMsg readPoseStamped(Reader& r)
{
    PoseMsg m;
    m.header = readHeader(r);
    m.position = readVector3(r);
    m.orientation = readQuaternion(r);
    return m;
}

TransformMsg readTransformStamped(Reader& r) { return readTransformBody(r); }

PoseMsg readOdometry(Reader& r)
{
    PoseMsg m;
    m.header = readHeader(r);
    r.string();  // child_frame_id
    m.position = readVector3(r);
    m.orientation = readQuaternion(r);
    std::array<double, 36> covariance;
    r.f64Array(covariance);  // the twist that follows is not needed
    return m;
}

std::vector<TransformMsg> readTFMessage(Reader& r)
{
    // A TransformStamped takes at least 4 + 4 + 4 + 4 + 7 x 8 bytes.
    const std::uint32_t n = r.sequenceLength(72);
    std::vector<TransformMsg> v;
    v.reserve(n);
    for (std::uint32_t i = 0; i < n; ++i) v.push_back(readTransformBody(r));
    return v;
}

std::vector<std::uint8_t> encode(const ImageMsg& m)
{
    Writer w;
    writeHeader(w, m.header);
    w.u32(m.height);
    w.u32(m.width);
    w.string(m.encoding);
    w.u8(m.is_bigendian ? 1 : 0);
    w.u32(m.step);
    w.byteSequence(m.data);
    return w.take();
}

std::vector<std::uint8_t> encode(const CompressedImageMsg& m)
{
    Writer w;
    writeHeader(w, m.header);
    w.string(m.format);
    w.byteSequence(m.data);
    return w.take();
}

std::vector<std::uint8_t> encode(const ImuMsg& m)
{
    Writer w;
    writeHeader(w, m.header);
    writeQuaternion(w, m.orientation);
    w.f64Array(m.orientation_covariance);
    writeVector3(w, m.angular_velocity);
    w.f64Array(m.angular_velocity_covariance);
    writeVector3(w, m.linear_acceleration);
    w.f64Array(m.linear_acceleration_covariance);
    return w.take();
}

std::vector<std::uint8_t> encode(const CameraInfoMsg& m)
{
    Writer w;
    writeHeader(w, m.header);
    w.u32(m.height);
    w.u32(m.width);
    w.string(m.distortion_model);
    w.f64Sequence(m.d);
    w.f64Array(m.k);
    w.f64Array(m.r);
    w.f64Array(m.p);
    for (int i = 0; i < 2 + 4; ++i) w.u32(0);  // no binning, full-image region of interest
    w.boolean(false);
    return w.take();
}

std::vector<std::uint8_t> encode(const PoseMsg& m)
{
    Writer w;
    writeHeader(w, m.header);
    writeVector3(w, m.position);
    writeQuaternion(w, m.orientation);
    return w.take();
}

std::vector<std::uint8_t> encodeTFMessage(const std::vector<TransformMsg>& transforms)
{
    Writer w;
    w.u32(std::uint32_t(transforms.size()));
    for (const auto& t : transforms) writeTransform(w, t);
    return w.take();
}

}  // namespace quasiloc::ros::cdr
