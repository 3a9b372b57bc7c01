// Field roles by the readers' naming conventions and points stored as records (point_records.h): what the PCD and PLY
// readers and map-build's PointCloud2 scans share.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <quasiloc/map/point_records.h>

#include "test_cloud_files.h"

using namespace quasiloc::map;
using namespace quasiloc::map::test;

TEST(PointRecords, RolesFollowTheReadersNamingConventions)
{
    const CloudFieldRoles c =
        cloudFieldRoles({"x", "y", "z", "i", "reflectivity", "intensity", "timestamp", "t", "line", "ring"});
    EXPECT_TRUE(c.hasXyz());
    EXPECT_EQ(c.intensity, 5);  // intensity before reflectivity before i
    EXPECT_EQ(c.time, 7);       // t (rank 2) before timestamp (rank 4)
    EXPECT_EQ(c.ring, 8);       // the first ring-like field
    const CloudFieldRoles masked = cloudFieldRoles({"x", "y", "z", "intensity"}, {true, true, true, false});
    EXPECT_EQ(masked.intensity, -1);
    EXPECT_FALSE(cloudFieldRoles({"X", "y", "z"}).hasXyz());  // positions are matched exactly
}

TEST(PointRecords, RingNumbersAreClampedAndNanIsZero)
{
    EXPECT_EQ(ringNumber(std::numeric_limits<double>::quiet_NaN()), 0);
    EXPECT_EQ(ringNumber(-3), 0);
    EXPECT_EQ(ringNumber(70000), 65535);
    EXPECT_EQ(ringNumber(12.7), 12);
}

TEST(PointRecords, DecodesRowsWithPaddingAndDropsPointsWithoutPosition)
{
    // 2 rows x 2 points of {float x, float y, float z, uint16 intensity, 2 pad}; rows padded to 40 bytes.
    std::vector<uint8_t> data(80, 0);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float xyz[4][3] = {{1, 2, 3}, {nan, 0, 0}, {4, 5, 6}, {7, 8, 9}};
    for (int k = 0; k < 4; ++k)
    {
        uint8_t* p = data.data() + (k / 2) * 40 + (k % 2) * 16;
        std::memcpy(p, xyz[k], 12);
        const uint16_t i = uint16_t(100 * k);
        std::memcpy(p + 12, &i, 2);
    }
    PointRecords r;
    r.fields = {{"x", 0, ScalarType::Float32, 1},
                {"y", 4, ScalarType::Float32, 1},
                {"z", 8, ScalarType::Float32, 1},
                {"intensity", 12, ScalarType::UInt16, 1}};
    r.data = data.data();
    r.bytes = data.size();
    r.rows = 2;
    r.columns = 2;
    r.point_step = 16;
    r.row_step = 40;
    const DecodedRecords d = decodePointRecords(r, "cloud");
    EXPECT_EQ(d.invalid, 1u);
    EXPECT_EQ(d.cloud.x, (std::vector<float>{1, 4, 7}));
    EXPECT_EQ(d.cloud.intensity, (std::vector<float>{0, 200, 300}));
    EXPECT_EQ(d.cloud.intensity_field, "intensity");
    r.bytes = 71;  // the last point needs bytes 56..72
    expectInputError([&] { decodePointRecords(r, "cloud"); }, "cloud", "truncated point data: 71 bytes");
}

TEST(PointRecords, NoColumnsIsAnEmptyCloudWhateverTheRows)
{
    // Found by fuzz_point_cloud2: 0 points per row of 2^31 rows walked every row (a timeout).
    PointRecords r;
    r.fields = {{"x", 0, ScalarType::Float32, 1},
                {"y", 4, ScalarType::Float32, 1},
                {"z", 8, ScalarType::Float32, 1},
                {"i", 12, ScalarType::Float32, 1}};
    r.rows = size_t(1) << 31;
    r.columns = 0;
    r.point_step = 16;
    const DecodedRecords d = decodePointRecords(r, "cloud");
    EXPECT_EQ(d.cloud.size(), 0u);
    EXPECT_EQ(d.invalid, 0u);
}
