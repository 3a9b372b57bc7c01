#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <quasiloc/map/cloud_export.h>
#include <quasiloc/map/map_import.h>

#include "test_cloud_files.h"

using namespace quasiloc::map;
using namespace quasiloc::map::test;

namespace
{
LidarMap randomMap(size_t n, uint32_t seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> P(-40.f, 40.f), R(0.f, 1.f);
    LidarMap m;
    for (size_t i = 0; i < n; ++i) m.addPoint(P(rng), P(rng), P(rng) * 0.1f, R(rng));
    return m;
}

void writeBytes(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }
}  // namespace

TEST(MapImport, FormatDetectionAndNames)
{
    EXPECT_EQ(detectCloudFormat("a/b/c.PLY"), CloudFormat::Ply);
    EXPECT_EQ(detectCloudFormat("scan.pcd"), CloudFormat::Pcd);
    EXPECT_EQ(detectCloudFormat("000000.bin"), CloudFormat::KittiBin);
    for (const char* f : {"a.txt", "a.xyz", "a.xyzi", "a.csv", "a.asc"})
        EXPECT_EQ(detectCloudFormat(f), CloudFormat::Xyzi);
    expectInputError([] { detectCloudFormat("cloud.las"); }, "cloud.las", "unknown point cloud format");
    expectInputError([] { detectCloudFormat("noext"); }, "noext", "unknown point cloud format");
    for (const CloudFormat f :
         {CloudFormat::Auto, CloudFormat::Ply, CloudFormat::Pcd, CloudFormat::KittiBin, CloudFormat::Xyzi})
        EXPECT_EQ(cloudFormatFromString(toString(f), "format"), f);
    expectInputError([] { cloudFormatFromString("las", "[MapImport] format"); }, "[MapImport] format",
                     "unknown cloud format");
    EXPECT_EQ(intensityFieldRank("Intensity"), 1);
    EXPECT_EQ(intensityFieldRank("scalar field"), 6);
    EXPECT_EQ(intensityFieldRank("rgb"), 0);
    EXPECT_EQ(intensityFieldRank("scalar_"), 0);
}

TEST(MapImport, ExportThenReadRoundTripsEveryFormatAndEncoding)
{
    TempDir dir;
    const LidarMap map = randomMap(500, 3);
    const struct
    {
        const char* file;
        CloudEncoding enc;
    } cases[] = {{"a.ply", CloudEncoding::Ascii},           {"b.ply", CloudEncoding::Binary},
                 {"c.ply", CloudEncoding::BinaryBigEndian}, {"d.pcd", CloudEncoding::Ascii},
                 {"e.pcd", CloudEncoding::Binary},          {"f.pcd", CloudEncoding::BinaryCompressed},
                 {"g.bin", CloudEncoding::Binary},          {"h.xyzi", CloudEncoding::Ascii}};
    for (const auto& c : cases)
    {
        SCOPED_TRACE(c.file);
        const std::string path = dir.file(c.file);
        exportCloud(map, path, CloudFormat::Auto, c.enc);
        const RawCloud cloud = readCloud(path);
        ASSERT_EQ(cloud.size(), map.size());
        for (size_t i = 0; i < map.size(); ++i)
        {
            ASSERT_EQ(cloud.x[i], map.xs()[i]);
            ASSERT_EQ(cloud.y[i], map.ys()[i]);
            ASSERT_EQ(cloud.z[i], map.zs()[i]);
            ASSERT_EQ(cloud.intensity[i], map.reflectivities()[i]);
        }
    }
    expectInputError([&] { exportCloud(map, dir.file("x.ply"), CloudFormat::Auto, CloudEncoding::BinaryCompressed); },
                     dir.file("x.ply"), "no binary_compressed");
    EXPECT_FALSE(std::filesystem::exists(dir.file("x.ply")));
}

TEST(MapImport, KittiBinReader)
{
    TempDir dir;
    const std::string path = dir.file("000000.bin");
    const float rec[3][4] = {{1.5f, -2.f, 0.25f, 0.5f}, {10.f, 20.f, 30.f, 0.f}, {-1.f, -1.f, -1.f, 1.f}};
    writeBytes(path, std::string(reinterpret_cast<const char*>(rec), sizeof(rec)));
    const RawCloud c = readCloud(path);
    ASSERT_EQ(c.size(), 3u);
    for (int i = 0; i < 3; ++i)
    {
        EXPECT_EQ(c.x[i], rec[i][0]);
        EXPECT_EQ(c.y[i], rec[i][1]);
        EXPECT_EQ(c.z[i], rec[i][2]);
        EXPECT_EQ(c.intensity[i], rec[i][3]);
    }
    writeBytes(path, std::string(reinterpret_cast<const char*>(rec), sizeof(rec) - 6));
    expectInputError([&] { readCloud(path); }, path, "truncated");
    writeBytes(path, "");
    expectInputError([&] { readCloud(path); }, path, "empty");
    float nan_rec[4] = {NAN, 0, 0, 0.5f};
    writeBytes(path, std::string(reinterpret_cast<const char*>(nan_rec), sizeof(nan_rec)));
    expectInputError([&] { readCloud(path); }, path, "point 0 has a non-finite");
}

TEST(MapImport, XyziTextReader)
{
    TempDir dir;
    const std::string path = dir.file("cloud.txt");
    writeBytes(path, "# x y z i\n1 2 3 0.5\n\n  4,5,6,7   # trailing comment\r\n-1e1\t2.5\t+3\t255\n7, 8 ,9 ,1");
    const RawCloud c = readCloud(path, CloudFormat::Xyzi);
    ASSERT_EQ(c.size(), 4u);
    EXPECT_FLOAT_EQ(c.x[1], 4.f);
    EXPECT_FLOAT_EQ(c.intensity[1], 7.f);
    EXPECT_FLOAT_EQ(c.x[2], -10.f);
    EXPECT_FLOAT_EQ(c.z[2], 3.f);
    EXPECT_FLOAT_EQ(c.intensity[2], 255.f);
    EXPECT_FLOAT_EQ(c.z[3], 9.f);

    writeBytes(path, "1 2 3 0.5\n1 2 3\n");
    expectInputError([&] { readCloud(path); }, path, "line 2: no intensity field");
    writeBytes(path, "1 2 3 0.5 9\n");
    expectInputError([&] { readCloud(path); }, path, "line 1: 5 values");
    writeBytes(path, "1 2 abc 0.5\n");
    expectInputError([&] { readCloud(path); }, path, "'abc' is not a number");
    writeBytes(path, "1 nan 3 0.5\n");
    expectInputError([&] { readCloud(path); }, path, "non-finite");
    writeBytes(path, "# only comments\n\n");
    expectInputError([&] { readCloud(path); }, path, "empty");
    const std::string missing = dir.file("nope.xyz");
    expectInputError([&] { readCloud(missing); }, missing, "not found");
    const std::string unknown = dir.file("cloud.las");
    writeBytes(unknown, "x");
    expectInputError([&] { readCloud(unknown); }, unknown, "unknown point cloud format");
}

TEST(MapImport, NormalisationRules)
{
    auto rule = [](std::vector<float> v, double scale = 0) { return chooseIntensityNormalisation(v, scale); };
    EXPECT_EQ(rule({0.f, 0.3f, 1.f}).divisor, 1.0);
    EXPECT_NE(rule({0.f, 0.3f, 1.f}).rule.find("kept"), std::string::npos);
    EXPECT_EQ(rule({0.f, 1.5f, 255.f}).divisor, 255.0);
    EXPECT_EQ(rule({0.f, 2.f}).divisor, 255.0);
    EXPECT_EQ(rule({-0.5f, 0.5f}).divisor, 255.0);  // not all within [0, 1]
    EXPECT_EQ(rule({0.f, 256.f}).divisor, 65535.0);
    EXPECT_EQ(rule({0.f, 65535.f}).divisor, 65535.0);
    EXPECT_EQ(rule({3.f, 70000.f}).divisor, 70000.0);
    EXPECT_NE(rule({3.f, 70000.f}).rule.find("maximum"), std::string::npos);
    const auto given = rule({0.f, 70000.f}, 4096);
    EXPECT_EQ(given.divisor, 4096.0);
    EXPECT_NE(given.rule.find("intensity_scale"), std::string::npos);
    EXPECT_EQ(given.raw_min, 0.f);
    EXPECT_EQ(given.raw_max, 70000.f);
    expectInputError([&] { rule({1.f}, -1); }, "intensity_scale", ">= 0");

    RawCloud c;
    for (float v : {-10.f, 0.f, 51.f, 255.f, 300.f}) c.push(v, 0, 0, v);
    IntensityNormalisation n = chooseIntensityNormalisation(c.intensity, 255);
    const LidarMap m = toLidarMap(c, n);
    EXPECT_EQ(n.clamped, 2u);  // -10 and 300
    const float expected[] = {0.f, 0.f, 0.2f, 1.f, 1.f};
    for (size_t i = 0; i < 5; ++i) EXPECT_FLOAT_EQ(m.reflectivity(i), expected[i]);
}

TEST(MapImport, VoxelDownsamplingValues)
{
    LidarMap m;
    // Voxel size 1: voxel (0,0,0) holds 3 points, voxel (-1,0,0) holds 1, voxel (2,5,-3) holds 2.
    m.addPoint(0.1f, 0.2f, 0.3f, 0.0f);
    m.addPoint(0.9f, 0.4f, 0.5f, 0.6f);
    m.addPoint(-0.5f, 0.5f, 0.5f, 0.7f);
    m.addPoint(0.5f, 0.9f, 0.1f, 0.3f);
    m.addPoint(2.5f, 5.5f, -2.5f, 1.0f);
    m.addPoint(2.1f, 5.1f, -2.9f, 0.0f);
    const LidarMap d = voxelDownsample(m, 1.0);
    ASSERT_EQ(d.size(), 3u);
    struct Expect
    {
        float x, y, z, r;
    };
    const Expect e[] = {{0.5f, 0.5f, 0.3f, 0.3f}, {-0.5f, 0.5f, 0.5f, 0.7f}, {2.3f, 5.3f, -2.7f, 0.5f}};
    for (const Expect& ex : e)
    {
        bool found = false;
        for (size_t i = 0; i < d.size(); ++i)
            if (std::abs(d.xs()[i] - ex.x) < 1e-5f && std::abs(d.ys()[i] - ex.y) < 1e-5f &&
                std::abs(d.zs()[i] - ex.z) < 1e-5f)
            {
                found = true;
                EXPECT_NEAR(d.reflectivity(i), ex.r, 1e-6f);
            }
        EXPECT_TRUE(found) << ex.x << " " << ex.y << " " << ex.z;
    }
    expectInputError([&] { voxelDownsample(m, 0.0); }, "voxel_size_m", "> 0");
    expectInputError([&] { voxelDownsample(m, 1e-7); }, "voxel_size_m", "too small");
}

TEST(MapImport, VoxelDownsamplingOfAMillionPoints)
{
    const LidarMap m = randomMap(1000000, 5);
    const LidarMap d = voxelDownsample(m, 0.5);
    // Every output point lies in a distinct voxel and the means stay inside the input's bounds.
    EXPECT_LT(d.size(), m.size());
    EXPECT_GT(d.size(), m.size() / 4);
    std::vector<uint64_t> keys;
    for (size_t i = 0; i < d.size(); ++i)
    {
        const auto k = [&](float v) { return static_cast<uint64_t>(std::floor(v / 0.5) + 1000); };
        keys.push_back((k(d.xs()[i]) << 42) | (k(d.ys()[i]) << 21) | k(d.zs()[i]));
    }
    std::sort(keys.begin(), keys.end());
    EXPECT_EQ(std::adjacent_find(keys.begin(), keys.end()), keys.end());
    const auto [lo, hi] = d.reflectivityRange();
    EXPECT_GE(lo, 0.f);
    EXPECT_LE(hi, 1.f);
}

TEST(MapImport, ImportPipelineWith8BitIntensities)
{
    TempDir dir;
    std::mt19937 rng(2);
    std::vector<Column> cols;
    for (const char* a : {"x", "y", "z"})
        cols.push_back({a, ScalarType::Float32, randomValues(1000, ScalarType::Float32, 0, 10, rng)});
    cols.push_back({"intensity", ScalarType::UInt8, randomValues(1000, ScalarType::UInt8, 0, 200, rng)});
    const std::string path = dir.file("eight_bit.pcd");
    writePcd(path, "binary_compressed", cols);
    ImportOptions o;
    o.voxel_size_m = 2.0;
    const ImportResult r = importCloud(path, o);
    EXPECT_EQ(r.format, CloudFormat::Pcd);
    EXPECT_EQ(r.points_read, 1000u);
    EXPECT_EQ(r.normalisation.divisor, 255.0);
    EXPECT_LE(r.map.size(), 125u);  // 10 m cube, 2 m voxels
    EXPECT_NO_THROW(r.map.check(path));
    expectInputError([&] { importCloud(dir.file("none.pcd"), o); }, dir.file("none.pcd"), "not found");
}

TEST(MapImport, RealKittiMapPly)
{
    const std::string path = std::string(QUASILOC_SHARED_DIR) + "/data/kitti_raw_seq78/map_even_frames_5cm.ply";
    const auto t0 = std::chrono::steady_clock::now();
    const ImportResult r = importCloud(path, ImportOptions{});
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(r.points_read, 1061716u);
    EXPECT_EQ(r.map.size(), 1061716u);
    EXPECT_EQ(r.intensity_field, "intensity");
    EXPECT_EQ(r.encoding, "binary_little_endian");
    EXPECT_EQ(r.normalisation.divisor, 1.0) << r.normalisation.rule;
    EXPECT_EQ(r.normalisation.clamped, 0u);
    const auto [lo, hi] = r.map.reflectivityRange();
    EXPECT_GE(lo, 0.f);
    EXPECT_LE(hi, 1.f);
    EXPECT_GT(hi, lo);
    EXPECT_NO_THROW(r.map.check(path));
    std::cout << "read " << r.map.summary() << " in " << s << " s\n";
}
