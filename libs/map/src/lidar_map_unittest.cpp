#include <gtest/gtest.h>

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/serialization/CArchive.h>
#include <quasiloc/map/lidar_map.h>

#include "test_cloud_files.h"

using namespace quasiloc::map;
using namespace quasiloc::map::test;

namespace
{
void serialize(const mrpt::serialization::CSerializable& obj, const std::string& path)
{
    mrpt::io::CFileGZOutputStream out(path);
    mrpt::serialization::archiveFrom(out) << obj;
}
}  // namespace

TEST(LidarMap, AccessorsBoundsAndSummary)
{
    LidarMap m;
    EXPECT_TRUE(m.empty());
    m.addPoint(1, 2, 3, 0.25f);
    m.addPoint(-1, 5, 0, 1.0f);
    m.addPoint(0, -4, 7, 0.5f);
    ASSERT_EQ(m.size(), 3u);
    EXPECT_EQ(m.point(1), Eigen::Vector3f(-1, 5, 0));
    EXPECT_EQ(m.reflectivity(2), 0.5f);
    const MapBounds b = m.bounds();
    EXPECT_EQ(b.min, Eigen::Vector3f(-1, -4, 0));
    EXPECT_EQ(b.max, Eigen::Vector3f(1, 5, 7));
    EXPECT_EQ(m.reflectivityRange(), std::make_pair(0.25f, 1.0f));
    EXPECT_EQ(m.summary(), "3 points, bounds [-1.00 -4.00 0.00]..[1.00 5.00 7.00] m, reflectivity [0.250, 1.000]");
    EXPECT_NO_THROW(m.check("m"));
}

TEST(LidarMap, SaveLoadRoundTripIsIdentical)
{
    TempDir dir;
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> P(-100.f, 100.f), R(0.f, 1.f);
    LidarMap m;
    for (int i = 0; i < 20000; ++i) m.addPoint(P(rng), P(rng), P(rng), R(rng));
    const std::string path = dir.file("sub/dir/room.map");
    m.save(path);
    const LidarMap back = LidarMap::load(path);
    ASSERT_EQ(back.size(), m.size());
    for (size_t i = 0; i < m.size(); ++i)
    {
        ASSERT_EQ(back.xs()[i], m.xs()[i]);
        ASSERT_EQ(back.ys()[i], m.ys()[i]);
        ASSERT_EQ(back.zs()[i], m.zs()[i]);
        ASSERT_EQ(back.reflectivities()[i], m.reflectivities()[i]);
    }
    // Only the map file is left: the temporary was renamed.
    size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir.file("sub/dir"))) files += e.is_regular_file();
    EXPECT_EQ(files, 1u);
}

TEST(LidarMap, LoadRejectsBadFiles)
{
    TempDir dir;
    const std::string missing = dir.file("missing.map");
    expectInputError([&] { LidarMap::load(missing); }, missing, "not found");

    const std::string garbage = dir.file("garbage.map");
    std::ofstream(garbage) << "this is not an MRPT archive at all";
    expectInputError([&] { LidarMap::load(garbage); }, garbage, "serialized MRPT map");

    const std::string wrong = dir.file("simple.map");
    mrpt::maps::CSimplePointsMap simple;
    simple.insertPoint(1, 2, 3);
    serialize(simple, wrong);
    expectInputError([&] { LidarMap::load(wrong); }, wrong, "CSimplePointsMap");

    const std::string empty = dir.file("empty.map");
    LidarMap().save(empty);
    expectInputError([&] { LidarMap::load(empty); }, empty, "empty");

    const std::string nan_map = dir.file("nan.map");
    mrpt::maps::CPointsMapXYZI pts;
    pts.insertPointRGB(0, 0, 0, 0.5f, 0, 0);
    pts.insertPointRGB(1, NAN, 0, 0.5f, 0, 0);
    serialize(pts, nan_map);
    expectInputError([&] { LidarMap::load(nan_map); }, nan_map, "point 1 has a non-finite");

    const std::string bright = dir.file("bright.map");
    pts.setPointFast(1, 1, 1, 1);
    pts.setPointIntensity(1, 3.0f);
    serialize(pts, bright);
    expectInputError([&] { LidarMap::load(bright); }, bright, "outside [0, 1]");

    const std::string cut = dir.file("cut.map");
    LidarMap big;
    for (int i = 0; i < 1000; ++i) big.addPoint(float(i), 0, 0, 0.5f);
    big.save(cut);
    std::filesystem::resize_file(cut, std::filesystem::file_size(cut) / 2);
    expectInputError([&] { LidarMap::load(cut); }, cut, "serialized MRPT map");
}

TEST(LidarMap, SaveToAnUnwritablePlaceThrowsAndLeavesNothing)
{
    TempDir dir;
    LidarMap m;
    m.addPoint(0, 0, 0, 0);
    const std::string blocker = dir.file("file");
    std::ofstream(blocker) << "x";
    EXPECT_THROW(m.save(blocker + "/inside.map"), std::exception);
    EXPECT_FALSE(std::filesystem::exists(blocker + "/inside.map"));
}
