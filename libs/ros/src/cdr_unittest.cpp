// The CDR codecs: every message type bag2rawlog reads comes back from its encoding field for field; big-endian
// encapsulation and alignment counted from the end of the 4-byte header; malformed messages are InputErrors naming
// the message.
#include <gtest/gtest.h>

#include <cstring>
#include <quasiloc/core/error.h>
#include <quasiloc/ros/cdr.h>

using namespace quasiloc::ros;

namespace
{
template <typename F>
auto decode(const std::vector<std::uint8_t>& bytes, F read)
{
    cdr::Reader r(bytes.data(), bytes.size(), "test message");
    auto m = read(r);
    EXPECT_EQ(r.remaining(), 0u);
    return m;
}

std::string errorOf(const std::vector<std::uint8_t>& bytes)
{
    try
    {
        cdr::Reader r(bytes.data(), bytes.size(), "bag.mcap topic /cam0/image_raw");
        cdr::readImage(r);
    }
    catch (const quasiloc::core::InputError& e)
    {
        return e.what();
    }
    return "(no error)";
}

/** A big-endian CDR writer of the few primitives the test needs (ours writes little endian only). */
struct BigEndian
{
    std::vector<std::uint8_t> b{0x00, 0x00, 0x00, 0x00};
    void align(std::size_t n)
    {
        while ((b.size() - 4) % n) b.push_back(0);
    }
    void u32(std::uint32_t v)
    {
        align(4);
        for (int i = 3; i >= 0; --i) b.push_back(std::uint8_t(v >> (8 * i)));
    }
    void f64(double d)
    {
        align(8);
        std::uint64_t v;
        std::memcpy(&v, &d, 8);
        for (int i = 7; i >= 0; --i) b.push_back(std::uint8_t(v >> (8 * i)));
    }
    void string(const std::string& s)
    {
        u32(std::uint32_t(s.size() + 1));
        b.insert(b.end(), s.begin(), s.end());
        b.push_back(0);
    }
};
}  // namespace

TEST(Cdr, EveryMessageTypeComesBackFromItsEncoding)
{
    ImageMsg img;
    img.header = {1700000000123456789LL, "cam0"};
    img.height = 2;
    img.width = 3;
    img.step = 3;
    img.encoding = "mono8";
    img.data = {1, 2, 3, 4, 5, 6};
    const ImageMsg img2 = decode(cdr::encode(img), cdr::readImage);
    EXPECT_EQ(img2.header.stamp_ns, img.header.stamp_ns);
    EXPECT_EQ(img2.header.frame_id, "cam0");
    EXPECT_EQ(img2.encoding, "mono8");
    EXPECT_EQ(img2.data, img.data);
    EXPECT_EQ(img2.step, 3u);

    ImuMsg imu;
    imu.header = {-1500000000LL, ""};  // before 1970: sec -2, nanosec 5e8
    imu.orientation = Eigen::Quaterniond(0.5, 0.5, -0.5, 0.5);
    imu.angular_velocity = {0.1, -0.2, 0.3};
    imu.linear_acceleration = {1, 2, 9.81};
    imu.linear_acceleration_covariance[8] = 0.04;
    const ImuMsg imu2 = decode(cdr::encode(imu), cdr::readImu);
    EXPECT_EQ(imu2.header.stamp_ns, imu.header.stamp_ns);
    EXPECT_EQ(imu2.orientation.coeffs(), imu.orientation.coeffs());
    EXPECT_EQ(imu2.angular_velocity, imu.angular_velocity);
    EXPECT_EQ(imu2.linear_acceleration, imu.linear_acceleration);
    EXPECT_EQ(imu2.linear_acceleration_covariance, imu.linear_acceleration_covariance);

    CameraInfoMsg info;
    info.header = {5, "cam1"};
    info.width = 848;
    info.height = 480;
    info.distortion_model = "plumb_bob";
    info.d = {0.1, -0.2, 0.001, 0.002, 0.0};
    info.k = {420, 0, 424, 0, 421, 240, 0, 0, 1};
    const CameraInfoMsg info2 = decode(cdr::encode(info), cdr::readCameraInfo);
    EXPECT_EQ(info2.d, info.d);
    EXPECT_EQ(info2.k, info.k);
    EXPECT_EQ(info2.width, 848u);

    CompressedImageMsg c;
    c.header = {7, "cam0"};
    c.format = "mono8; png compressed";
    c.data = {9, 8, 7};
    const CompressedImageMsg c2 = decode(cdr::encode(c), cdr::readCompressedImage);
    EXPECT_EQ(c2.format, c.format);
    EXPECT_EQ(c2.data, c.data);

    PoseMsg pose;
    pose.header = {8, "world"};
    pose.position = {1, 2, 3};
    pose.orientation = Eigen::Quaterniond(0, 1, 0, 0);
    const PoseMsg pose2 = decode(cdr::encode(pose), cdr::readPoseStamped);
    EXPECT_EQ(pose2.position, pose.position);
    EXPECT_EQ(pose2.orientation.coeffs(), pose.orientation.coeffs());

    TransformMsg t;
    t.header = {9, "base_link"};
    t.child_frame_id = "imu_link";
    t.translation = {0.1, 0, 0.2};
    const auto tf = decode(cdr::encodeTFMessage({t, t}), cdr::readTFMessage);
    ASSERT_EQ(tf.size(), 2u);
    EXPECT_EQ(tf[1].child_frame_id, "imu_link");
    EXPECT_EQ(tf[1].header.frame_id, "base_link");
    EXPECT_EQ(tf[1].translation, t.translation);
}

TEST(Cdr, BigEndianMessagesAlignFromTheEndOfTheHeader)
{
    // geometry_msgs/PoseStamped, big endian: stamp, frame "map" (4 + 4 bytes: the doubles start at 16, aligned to 8
    // counted after the encapsulation header), position, orientation.
    BigEndian be;
    be.u32(12);         // sec
    be.u32(500000000);  // nanosec
    be.string("map");   // ends at 12: 4 bytes of padding before the first double
    for (double v : {1.5, -2.5, 3.25, 0.0, 0.0, 0.0, 1.0}) be.f64(v);
    EXPECT_EQ(be.b.size(), 4u + 16u + 56u);
    const PoseMsg p = decode(be.b, cdr::readPoseStamped);
    EXPECT_EQ(p.header.stamp_ns, 12500000000LL);
    EXPECT_EQ(p.header.frame_id, "map");
    EXPECT_EQ(p.position, Eigen::Vector3d(1.5, -2.5, 3.25));
    EXPECT_EQ(p.orientation.w(), 1.0);
}

TEST(Cdr, MalformedMessagesAreErrorsNamingTheMessage)
{
    ImageMsg img;
    img.header = {1, "cam0"};
    img.encoding = "mono8";
    img.data = std::vector<std::uint8_t>(100, 7);
    const std::vector<std::uint8_t> good = cdr::encode(img);
    // Cut short: inside the data.
    std::vector<std::uint8_t> cut(good.begin(), good.end() - 10);
    std::string e = errorOf(cut);
    EXPECT_NE(e.find("bag.mcap topic /cam0/image_raw"), std::string::npos) << e;
    EXPECT_NE(e.find("sequence of 100 elements"), std::string::npos) << e;
    // XCDR2 (encapsulation 0x00 0x07) and parameter lists are not read.
    std::vector<std::uint8_t> xcdr2 = good;
    xcdr2[1] = 0x07;
    e = errorOf(xcdr2);
    EXPECT_NE(e.find("encapsulation"), std::string::npos) << e;
    // The frame_id's NUL replaced.
    std::vector<std::uint8_t> nonul = good;
    nonul[4 + 8 + 4 + 4] = 'x';  // header (4), stamp (8), length (4), "cam0" (4): its NUL
    e = errorOf(nonul);
    EXPECT_NE(e.find("NUL"), std::string::npos) << e;
    // A nanosec of a second or more.
    std::vector<std::uint8_t> ns = good;
    ns[8] = ns[9] = ns[10] = ns[11] = 0xFF;
    e = errorOf(ns);
    EXPECT_NE(e.find("nanosec"), std::string::npos) << e;
    e = errorOf({0x00, 0x01});
    EXPECT_NE(e.find("shorter than its 4-byte header"), std::string::npos) << e;
}
