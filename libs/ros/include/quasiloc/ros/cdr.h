#pragma once
// OMG CDR (XCDR version 1, "plain CDR"), the serialisation of ROS 2 messages in rosbag2 files: a 4-byte
// encapsulation header (0x00 0x00 = big endian, 0x00 0x01 = little endian, then 2 option bytes), then the fields in
// declaration order, each primitive aligned to its own size (at most 8) counted from the end of that header.
// Strings: uint32 length including the terminating NUL, the bytes, the NUL. Sequences: uint32 count, the elements.
// Fixed-size arrays: the elements alone.
//
// The decoders of the message types bag2rawlog reads (messages.h) and the encoders rawlog2bag writes.
#include <cstdint>
#include <quasiloc/ros/messages.h>
#include <string>
#include <vector>

namespace quasiloc::ros::cdr
{
/** Reads one CDR message. Every error (a short buffer, an unsupported encapsulation, a length beyond the end, a
 *  string without its NUL) is an InputError naming `where` (the file, topic and message). */
class Reader
{
   public:
    Reader(const std::uint8_t* data, std::size_t size, std::string where);

    bool boolean() { return u8() != 0; }
    std::uint8_t u8() { return primitive<std::uint8_t>(); }
    std::uint16_t u16() { return primitive<std::uint16_t>(); }
    std::uint32_t u32() { return primitive<std::uint32_t>(); }
    std::int32_t i32() { return std::int32_t(primitive<std::uint32_t>()); }
    std::uint64_t u64() { return primitive<std::uint64_t>(); }
    std::int64_t i64() { return std::int64_t(primitive<std::uint64_t>()); }
    float f32();
    double f64();
    std::string string();
    /** A sequence's element count, checked against the bytes left (each element at least `min_element_bytes`). */
    std::uint32_t sequenceLength(std::size_t min_element_bytes);
    std::vector<std::uint8_t> byteSequence();
    std::vector<double> f64Sequence();
    template <std::size_t N>
    void f64Array(std::array<double, N>& out)
    {
        for (auto& v : out) v = f64();
    }
    std::size_t remaining() const { return size_ - pos_; }
    const std::string& where() const { return where_; }

   private:
    template <typename T>
    T primitive();
    void align(std::size_t n);
    void need(std::size_t n, const char* what) const;

    const std::uint8_t* body_;  ///< after the encapsulation header
    std::size_t size_ = 0, pos_ = 0;
    bool swap_ = false;
    std::string where_;
};

/** Writes one little-endian CDR message (encapsulation 0x00 0x01 0x00 0x00). */
class Writer
{
   public:
    Writer();
    void boolean(bool v) { u8(v ? 1 : 0); }
    void u8(std::uint8_t v) { primitive(v); }
    void u32(std::uint32_t v) { primitive(v); }
    void i32(std::int32_t v) { primitive(std::uint32_t(v)); }
    void f64(double v);
    void string(const std::string& s);
    void byteSequence(const std::vector<std::uint8_t>& bytes);
    void f64Sequence(const std::vector<double>& v);
    template <std::size_t N>
    void f64Array(const std::array<double, N>& a)
    {
        for (double v : a) f64(v);
    }
    std::vector<std::uint8_t> take() { return std::move(bytes_); }

   private:
    template <typename T>
    void primitive(T v);
    void align(std::size_t n);
    std::vector<std::uint8_t> bytes_;
};

// Decoders: the whole message, InputError naming the Reader's `where` on any problem.
MsgHeader readHeader(Reader& r);
ImageMsg readImage(Reader& r);
CompressedImageMsg readCompressedImage(Reader& r);
ImuMsg readImu(Reader& r);
CameraInfoMsg readCameraInfo(Reader& r);
PoseMsg readPoseStamped(Reader& r);
TransformMsg readTransformStamped(Reader& r);
PoseMsg readOdometry(Reader& r);
std::vector<TransformMsg> readTFMessage(Reader& r);

/** std_msgs/Header: builtin_interfaces/Time (int32 sec, uint32 nanosec), then frame_id. */
void writeHeader(Writer& w, const MsgHeader& h);

// Encoders (a complete message with its encapsulation header).
std::vector<std::uint8_t> encode(const ImageMsg& m);
std::vector<std::uint8_t> encode(const CompressedImageMsg& m);
std::vector<std::uint8_t> encode(const ImuMsg& m);
std::vector<std::uint8_t> encode(const CameraInfoMsg& m);
std::vector<std::uint8_t> encode(const PoseMsg& m);  ///< as geometry_msgs/PoseStamped
std::vector<std::uint8_t> encodeTFMessage(const std::vector<TransformMsg>& transforms);

}  // namespace quasiloc::ros::cdr
