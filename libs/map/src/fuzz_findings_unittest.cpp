// Regression tests for what fuzzing the map readers found (fuzz/, docs/fuzzing.md): each input, cut down to what
// matters, must end in an InputError naming the input, not in undefined behaviour or a huge allocation.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <quasiloc/map/gmm.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/map/lzf.h>
#include <quasiloc/map/map_import.h>

#include "test_cloud_files.h"

using namespace quasiloc::map;
using namespace quasiloc::map::test;

namespace
{
std::vector<uint8_t> bytes(const std::string& s) { return std::vector<uint8_t>(s.begin(), s.end()); }

void expectCloudError(const std::string& content, CloudFormat format, const std::string& fragment)
{
    expectInputError([&] { readCloudBytes(bytes(content), format, "input.cloud"); }, "input.cloud", fragment);
}

template <class T>
std::string raw(T v)
{
    return std::string(reinterpret_cast<const char*>(&v), sizeof v);
}

const std::string kPcdFields = "FIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\n";
}  // namespace

// fuzz_ply: "element vertex 6e23" was cast to size_t (undefined behaviour, UBSan) and sized reserve() and loops.
TEST(FuzzFindings, PlyElementCountBeyondTheFileIsAnError)
{
    for (const char* count : {"6e23", "1e300", "inf", "4000"})
        expectCloudError(std::string("ply\nformat ascii 1.0\nelement vertex ") + count +
                             "\nproperty float x\nproperty float y\nproperty float z\nproperty float i\nend_header\n"
                             "1 2 3 4\n",
                         CloudFormat::Ply, "bad element count");
}

// Same cast for a list length stored as a float (or NaN) in binary data.
TEST(FuzzFindings, PlyListLengthThatIsNotACountIsAnError)
{
    for (const float length : {1e30f, std::nanf(""), -1.f, 2.5f})
        expectCloudError(
            "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
            "property float z\nproperty float i\nproperty list float uchar extra\nend_header\n" +
                raw(1.f) + raw(2.f) + raw(3.f) + raw(4.f) + raw(length) + "abc",
            CloudFormat::Ply, "bad list length");
}

// fuzz_pcd: "WIDTH 1e20" was cast to size_t (undefined behaviour, UBSan).
TEST(FuzzFindings, PcdHugeCountIsAnError)
{
    expectCloudError(kPcdFields + "WIDTH 1e20\nHEIGHT 1\nDATA ascii\n1 2 3 4\n", CloudFormat::Pcd, "bad WIDTH");
    expectCloudError(kPcdFields + "WIDTH 1\nHEIGHT 1\nPOINTS 5e100\nDATA ascii\n1 2 3 4\n", CloudFormat::Pcd,
                     "bad POINTS");
}

// WIDTH * HEIGHT and POINTS * record size wrapped around, so a small product passed the size checks.
TEST(FuzzFindings, PcdCountProductsThatOverflowAreErrors)
{
    expectCloudError(kPcdFields + "WIDTH 8589934592\nHEIGHT 8589934592\nDATA binary\n", CloudFormat::Pcd,
                     "WIDTH * HEIGHT overflows");
    expectCloudError(
        "FIELDS x y z intensity\nSIZE 8 4 4 4\nTYPE F F F F\nCOUNT 1099511627776 1 1 1\n"
        "WIDTH 1099511627776\nHEIGHT 1\nDATA binary\n" +
            std::string(64, '\0'),
        CloudFormat::Pcd, "truncated binary data");
}

// fuzz_pcd (in the 10-minute run): fields with COUNT 0 made a record of 0 bytes, so no data was needed, yet the first
// value of each field was read: a heap-buffer-overflow (ASan) past the end of the file's bytes.
TEST(FuzzFindings, PcdFieldWithCountZeroIsAnError)
{
    for (const char* data : {"binary", "binary_compressed", "ascii"})
        expectCloudError(
            "FIELDS x y z intensity\nSIZE 8 4 4 4\nTYPE I F F F\nCOUNT 0 0 0 0\nWIDTH 37\nHEIGHT 1\n"
            "DATA " +
                std::string(data) + "\n\xf3\xf3",
            CloudFormat::Pcd, "has COUNT 0");
}

// binary_compressed: the announced uncompressed size (up to 4 GB) was allocated before the 8 compressed bytes were
// found to be corrupt.
TEST(FuzzFindings, PcdCompressedSizeBeyondWhatLzfCanExpandIsAnError)
{
    const uint32_t points = 1u << 26, uncompressed = points * 16;
    expectCloudError(kPcdFields + "WIDTH " + std::to_string(points) + "\nHEIGHT 1\nDATA binary_compressed\n" +
                         raw(uint32_t(8)) + raw(uncompressed) + std::string(8, '\x1f'),
                     CloudFormat::Pcd, "LZF expands at most");
}

// fuzz_lidar_map: MRPT's CPointsMapXYZI::serializeFrom resized to the stored point count (malloc of 3.9 to 17 GB).
TEST(FuzzFindings, LidarMapPointCountBeyondTheFileIsAnError)
{
    TempDir dir;
    const std::string good = dir.file("good.map"), bad = dir.file("bad.map");
    LidarMap m;
    for (int i = 0; i < 5; ++i) m.addPoint(float(i), 0, 1, 0.5f);
    m.save(good);
    // An uncompressed archive (gzip reads it as is): the object header (0x80 | name length, class name, version
    // byte), then the uint32 point count, here 4 G points in a 231-byte file.
    const std::string name = "mrpt::maps::CPointsMapXYZI";
    const std::string archive =
        std::string(1, char(0x80 | name.size())) + name + '\0' + raw(uint32_t(0xF0000000u)) + std::string(200, '\0');
    std::ofstream(bad, std::ios::binary) << archive;
    expectInputError([&] { LidarMap::load(bad); }, bad, "points announced");
    EXPECT_EQ(LidarMap::load(good).size(), 5u);
}

// fuzz_gmm (by reading the code while fuzzing: 5,000 runs in 17 s): the announced component count sized a reserve
// of up to 16 M components (1.7 GB) per input.
TEST(FuzzFindings, GmmHugeComponentCountIsAnErrorWithoutAHugeReserve)
{
    const std::vector<uint8_t> file = {0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x10};  // varint 2^60
    expectInputError([&] { decodeGmm(file, "huge.gmm"); }, "huge.gmm", "header announces");
}
