// PointCloud2 decoding: hand-built messages (float32 / float64 positions, integer intensities, ring and time fields
// of the drivers' conventions, big-endian data, organised clouds with NaN points and padded rows) through CDR and
// scanFromPointCloud2, the bad layouts it refuses, and a PointCloud2 written by another library (rosbags).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <quasiloc/core/error.h>
#include <quasiloc/ros/point_cloud2.h>

#include "rosbag2_test_helpers.h"

namespace quasiloc::ros
{
namespace
{
using F = PointFieldMsg;

struct Field
{
    std::string name;
    std::uint8_t datatype;
};

std::size_t sizeOf(std::uint8_t datatype)
{
    static const std::size_t sizes[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};
    return sizes[datatype];
}

/** Stores v as the datatype at p, in the given byte order. */
void store(std::uint8_t* p, std::uint8_t datatype, double v, bool big_endian)
{
    std::uint8_t b[8];
    switch (datatype)
    {
        case F::kInt8: b[0] = std::uint8_t(std::int8_t(v)); break;
        case F::kUInt8: b[0] = std::uint8_t(v); break;
#define QUASILOC_STORE(K, T)           \
    case K:                            \
    {                                  \
        const T x = T(v);              \
        std::memcpy(b, &x, sizeof(T)); \
        break;                         \
    }
            QUASILOC_STORE(F::kInt16, std::int16_t)
            QUASILOC_STORE(F::kUInt16, std::uint16_t)
            QUASILOC_STORE(F::kInt32, std::int32_t)
            QUASILOC_STORE(F::kUInt32, std::uint32_t)
            QUASILOC_STORE(F::kFloat32, float)
            QUASILOC_STORE(F::kFloat64, double)
#undef QUASILOC_STORE
    }
    const std::size_t n = sizeOf(datatype);
    for (std::size_t k = 0; k < n; ++k) p[k] = big_endian ? b[n - 1 - k] : b[k];
}

/** A message of `rows` x `values.size() / rows` points, fields packed in order (+ `pad` bytes per point and
 *  `row_pad` per row); values[i][f] is field f of point i. */
PointCloud2Msg makeCloud(const std::vector<Field>& fields, const std::vector<std::vector<double>>& values,
                         std::uint32_t rows = 1, bool big_endian = false, std::uint32_t pad = 0,
                         std::uint32_t row_pad = 0)
{
    PointCloud2Msg m;
    m.header = {1317000000123456789, "lidar"};
    std::uint32_t offset = 0;
    for (const Field& f : fields)
    {
        m.fields.push_back({f.name, offset, f.datatype, 1});
        offset += std::uint32_t(sizeOf(f.datatype));
    }
    m.point_step = offset + pad;
    m.height = rows;
    m.width = std::uint32_t(values.size()) / rows;
    m.row_step = m.width * m.point_step + row_pad;
    m.is_bigendian = big_endian;
    m.data.assign(std::size_t(m.row_step) * rows, 0xAB);
    for (std::size_t i = 0; i < values.size(); ++i)
    {
        const std::size_t r = i / m.width, c = i % m.width;
        for (std::size_t f = 0; f < fields.size(); ++f)
            store(m.data.data() + r * m.row_step + c * m.point_step + m.fields[f].offset, fields[f].datatype,
                  values[i][f], big_endian);
    }
    return m;
}

/** Through CDR and back, then to a scan. */
map::LidarScan viaCdr(const PointCloud2Msg& m)
{
    const std::vector<std::uint8_t> bytes = cdr::encode(m);
    cdr::Reader r(bytes.data(), bytes.size(), "test");
    const PointCloud2Msg back = cdr::readPointCloud2(r);
    EXPECT_EQ(r.remaining(), 0u);
    EXPECT_EQ(back.header.stamp_ns, m.header.stamp_ns);
    EXPECT_EQ(back.data, m.data);
    return scanFromPointCloud2(back, "bag topic /points message 7");
}

const std::vector<Field> kXyzi32 = {
    {"x", F::kFloat32}, {"y", F::kFloat32}, {"z", F::kFloat32}, {"intensity", F::kFloat32}};

std::string errorOf(const PointCloud2Msg& m)
{
    return test::errorOf([&] { scanFromPointCloud2(m, "bag message 3"); });
}
}  // namespace

TEST(PointCloud2, Float32PositionsComeBackThroughCdr)
{
    const map::LidarScan s = viaCdr(makeCloud(kXyzi32, {{1.5, -2.25, 3, 0.5}, {10.125, 0, -1, 0.75}}));
    ASSERT_EQ(s.size(), 2u);
    EXPECT_EQ(s.points[0], Eigen::Vector3f(1.5f, -2.25f, 3.f));
    EXPECT_EQ(s.points[1], Eigen::Vector3f(10.125f, 0.f, -1.f));
    EXPECT_EQ(s.intensity, (std::vector<float>{0.5f, 0.75f}));
    EXPECT_TRUE(s.time_s.empty());
    EXPECT_TRUE(s.ring.empty());
    EXPECT_EQ(s.invalid_points, 0u);
}

TEST(PointCloud2, Float64PositionsUint16RingFloat32Time)
{
    // The Velodyne ROS driver's fields, with float64 positions and an 8-bit intensity.
    const std::vector<Field> fields = {{"x", F::kFloat64},       {"y", F::kFloat64},   {"z", F::kFloat64},
                                       {"intensity", F::kUInt8}, {"ring", F::kUInt16}, {"time", F::kFloat32}};
    const map::LidarScan s =
        viaCdr(makeCloud(fields, {{0.1, 0.2, 0.3, 200, 31, -0.05}, {4, 5, 6, 7, 0, 0.025}}, 1, false, /*pad=*/3));
    ASSERT_EQ(s.size(), 2u);
    EXPECT_EQ(s.points[0], Eigen::Vector3f(0.1f, 0.2f, 0.3f));  // float64 -> float as the file readers do
    EXPECT_EQ(s.intensity, (std::vector<float>{200.f, 7.f}));
    EXPECT_EQ(s.ring, (std::vector<std::uint16_t>{31, 0}));
    ASSERT_EQ(s.time_s.size(), 2u);
    EXPECT_DOUBLE_EQ(s.time_s[0], double(-0.05f));  // "time": seconds from the stamp
    EXPECT_DOUBLE_EQ(s.time_s[1], double(0.025f));
    EXPECT_FALSE(s.time_absolute);
}

TEST(PointCloud2, OusterAndHesaiTimeUnits)
{
    // Ouster: t in nanoseconds (uint32), reflectivity (uint16) and intensity: intensity wins, as in the file readers.
    const map::LidarScan ouster = viaCdr(makeCloud({{"x", F::kFloat32},
                                                    {"y", F::kFloat32},
                                                    {"z", F::kFloat32},
                                                    {"t", F::kUInt32},
                                                    {"reflectivity", F::kUInt16},
                                                    {"intensity", F::kFloat32},
                                                    {"ring", F::kUInt8}},
                                                   {{1, 2, 3, 50000000, 900, 12, 127}}));
    ASSERT_EQ(ouster.time_s.size(), 1u);
    EXPECT_DOUBLE_EQ(ouster.time_s[0], 0.05);
    EXPECT_EQ(ouster.intensity[0], 12.f);
    EXPECT_EQ(ouster.ring[0], 127);
    // Hesai: timestamp in absolute seconds (float64), ring uint16; reflectivity alone is the intensity.
    const map::LidarScan hesai = viaCdr(makeCloud({{"x", F::kFloat32},
                                                   {"y", F::kFloat32},
                                                   {"z", F::kFloat32},
                                                   {"reflectivity", F::kUInt8},
                                                   {"timestamp", F::kFloat64},
                                                   {"ring", F::kUInt16}},
                                                  {{1, 2, 3, 80, 1317000000.0625, 5}}));
    EXPECT_TRUE(hesai.time_absolute);
    EXPECT_DOUBLE_EQ(hesai.time_s[0], 1317000000.0625);
    EXPECT_EQ(hesai.intensity[0], 80.f);
    // Livox: offset_time in nanoseconds, line as the ring.
    const map::LidarScan livox = viaCdr(makeCloud({{"x", F::kFloat32},
                                                   {"y", F::kFloat32},
                                                   {"z", F::kFloat32},
                                                   {"intensity", F::kFloat32},
                                                   {"line", F::kUInt8},
                                                   {"offset_time", F::kUInt32}},
                                                  {{1, 2, 3, 10, 3, 1000}}));
    EXPECT_DOUBLE_EQ(livox.time_s[0], 1e-6);
    EXPECT_EQ(livox.ring[0], 3);
}

TEST(PointCloud2, BigEndianDataDecodesToTheSameScan)
{
    const std::vector<Field> fields = {{"x", F::kFloat64},       {"y", F::kFloat32},   {"z", F::kFloat32},
                                       {"intensity", F::kInt16}, {"ring", F::kUInt16}, {"time", F::kFloat64}};
    const std::vector<std::vector<double>> values = {{1.25, -2.5, 3.75, -300, 63, 0.0123}, {-7, 8, 9, 32000, 1, 0.05}};
    const map::LidarScan little = viaCdr(makeCloud(fields, values, 1, false));
    const PointCloud2Msg big_msg = makeCloud(fields, values, 1, true);
    EXPECT_NE(big_msg.data, makeCloud(fields, values, 1, false).data);
    const map::LidarScan big = viaCdr(big_msg);
    EXPECT_EQ(big.points, little.points);
    EXPECT_EQ(big.intensity, little.intensity);
    EXPECT_EQ(big.intensity[0], -300.f);
    EXPECT_EQ(big.ring, little.ring);
    EXPECT_EQ(big.time_s, little.time_s);
    EXPECT_EQ(big.points[0], Eigen::Vector3f(1.25f, -2.5f, 3.75f));
}

TEST(PointCloud2, OrganisedCloudDropsNanPointsAndSkipsRowPadding)
{
    const double nan = std::numeric_limits<double>::quiet_NaN();
    // 2 rows of 3 points, 5 bytes of padding after each point and 7 after each row; 2 invalid returns.
    const map::LidarScan s = viaCdr(makeCloud(
        kXyzi32, {{1, 1, 1, 1}, {nan, nan, nan, nan}, {2, 2, 2, 2}, {3, 3, 3, 3}, {4, 4, 4, 4}, {nan, 0, 0, 0}}, 2,
        false, 5, 7));
    ASSERT_EQ(s.size(), 4u);
    EXPECT_EQ(s.invalid_points, 2u);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(s.points[size_t(k)], Eigen::Vector3f::Constant(float(k + 1)));
    EXPECT_EQ(s.intensity, (std::vector<float>{1, 2, 3, 4}));
}

TEST(PointCloud2, TruncatedDataIsAnErrorNamingTheMessage)
{
    PointCloud2Msg m = makeCloud(kXyzi32, {{1, 1, 1, 1}, {2, 2, 2, 2}, {3, 3, 3, 3}, {4, 4, 4, 4}}, 2);
    m.data.resize(m.data.size() - 1);
    const std::string e = errorOf(m);
    EXPECT_NE(e.find("bag message 3: truncated point data: 63 bytes, 2 rows of 2 points (row_step 32, point_step 16) "
                     "need 64"),
              std::string::npos)
        << e;
    m.data.resize(m.data.size() + 1);
    m.row_step = 16;  // shorter than a row
    EXPECT_NE(errorOf(m).find("row_step 16 is shorter than a row of 2 points of 16 bytes"), std::string::npos);
}

TEST(PointCloud2, BadLayoutsAreErrors)
{
    PointCloud2Msg no_x =
        makeCloud({{"a", F::kFloat32}, {"y", F::kFloat32}, {"z", F::kFloat32}, {"i", F::kFloat32}}, {{1, 2, 3, 4}});
    EXPECT_NE(errorOf(no_x).find("bag message 3: fields lack x, y or z (fields: a y z i)"), std::string::npos);
    PointCloud2Msg no_i = makeCloud({{"x", F::kFloat32}, {"y", F::kFloat32}, {"z", F::kFloat32}}, {{1, 2, 3}});
    EXPECT_NE(errorOf(no_i).find("no intensity field"), std::string::npos);
    PointCloud2Msg int_x =
        makeCloud({{"x", F::kInt16}, {"y", F::kFloat32}, {"z", F::kFloat32}, {"i", F::kFloat32}}, {{1, 2, 3, 4}});
    EXPECT_NE(errorOf(int_x).find("field x is not float32 or float64"), std::string::npos);
    PointCloud2Msg beyond = makeCloud(kXyzi32, {{1, 2, 3, 4}});
    beyond.fields[3].offset = 14;
    EXPECT_NE(errorOf(beyond).find("field intensity (4 bytes at offset 14) does not fit in a point of point_step 16"),
              std::string::npos);
    PointCloud2Msg bad_type = makeCloud(kXyzi32, {{1, 2, 3, 4}});
    bad_type.fields[1].datatype = 9;
    EXPECT_NE(errorOf(bad_type).find("field y has datatype 9"), std::string::npos);
    bad_type.fields[1].datatype = F::kFloat32;
    bad_type.fields.push_back({"vendor", 0, 42, 1});  // an unknown datatype in a field not read: left out
    EXPECT_EQ(scanFromPointCloud2(bad_type, "m").size(), 1u);
    PointCloud2Msg nan_intensity = makeCloud(kXyzi32, {{1, 2, 3, std::nan("")}});
    EXPECT_NE(errorOf(nan_intensity).find("point 0 has a position and a non-finite intensity"), std::string::npos);
    PointCloud2Msg count0 = makeCloud(kXyzi32, {{1, 2, 3, 4}});
    count0.fields[2].count = 0;
    EXPECT_NE(errorOf(count0).find("field z has count 0"), std::string::npos);
}

TEST(PointCloud2, EmptyCloudIsAnEmptyScan)
{
    PointCloud2Msg m = makeCloud(kXyzi32, {});
    m.height = 0;
    EXPECT_EQ(viaCdr(m).size(), 0u);
}

TEST(PointCloud2, CutCdrMessageIsAnError)
{
    const std::vector<std::uint8_t> bytes = cdr::encode(makeCloud(kXyzi32, {{1, 2, 3, 4}}));
    for (std::size_t n : {std::size_t(3), std::size_t(20), bytes.size() - 8})
    {
        const std::string e = test::errorOf([&] {
            cdr::Reader r(bytes.data(), n, "cut");
            cdr::readPointCloud2(r);
        });
        EXPECT_EQ(e.rfind("cut: ", 0), 0u) << e;
    }
}

TEST(PointCloud2, MessageWrittenByAnotherLibraryDecodes)
{
    // rosbags (Python) 0.10.10 wrote this CDR: 3 points x y z float32, no intensity.
    QUASILOC_REQUIRE_ROS2_DATA();
    for (const std::string bag :
         {"rosbags_rs_all_types_sqlite3/test_bag_sqlite3.db3", "rosbags_rs_all_types_mcap/test_bag_mcap.mcap"})
    {
        int seen = 0;
        openMessageSource(test::ros2Data(bag))->read({"/test/sensor_msgs/point_cloud2"}, [&](const BagMessage& msg) {
            const PointCloud2Msg m = msg.pointCloud2();
            EXPECT_EQ(m.header.frame_id, "test_frame");
            EXPECT_EQ(m.height, 1u);
            EXPECT_EQ(m.width, 3u);
            EXPECT_EQ(m.fields.size(), 3u);
            if (m.fields.size() == 3)
            {
                EXPECT_EQ(m.fields[2].name, "z");
                EXPECT_EQ(m.fields[2].offset, 8u);
                EXPECT_EQ(m.fields[2].datatype, F::kFloat32);
            }
            EXPECT_EQ(m.point_step, 12u);
            EXPECT_EQ(m.row_step, 36u);
            EXPECT_EQ(m.data.size(), 36u);
            EXPECT_TRUE(m.is_dense);
            EXPECT_NE(errorOf(m).find("no intensity field"), std::string::npos);
            ++seen;
            return true;
        });
        EXPECT_EQ(seen, 2) << bag;
    }
}

}  // namespace quasiloc::ros
