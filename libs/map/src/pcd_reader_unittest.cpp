#include <gtest/gtest.h>

#include <cmath>
#include <quasiloc/map/map_import.h>

#include "test_cloud_files.h"

using namespace quasiloc::map;
using namespace quasiloc::map::test;

namespace
{
const char* kDataEncodings[] = {"ascii", "binary", "binary_compressed"};

std::vector<Column> makeColumns(size_t n, ScalarType coord_type, const std::string& iname, ScalarType itype, double ilo,
                                double ihi, uint32_t seed)
{
    std::mt19937 rng(seed);
    std::vector<Column> cols;
    for (const char* axis : {"x", "y", "z"})
        cols.push_back({axis, coord_type, randomValues(n, coord_type, -80, 80, rng)});
    cols.push_back({iname, itype, randomValues(n, itype, ilo, ihi, rng)});
    return cols;
}

void expectSameCloud(const RawCloud& c, const std::vector<Column>& cols, const std::string& iname)
{
    int xi = -1, yi = -1, zi = -1, ii = -1;
    for (size_t k = 0; k < cols.size(); ++k)
    {
        if (cols[k].name == "x") xi = int(k);
        if (cols[k].name == "y") yi = int(k);
        if (cols[k].name == "z") zi = int(k);
        if (cols[k].name == iname) ii = int(k);
    }
    ASSERT_EQ(c.size(), cols[0].values.size());
    EXPECT_EQ(c.intensity_field, iname);
    for (size_t i = 0; i < c.size(); ++i)
    {
        ASSERT_EQ(c.x[i], static_cast<float>(cols[xi].values[i])) << "point " << i;
        ASSERT_EQ(c.y[i], static_cast<float>(cols[yi].values[i])) << "point " << i;
        ASSERT_EQ(c.z[i], static_cast<float>(cols[zi].values[i])) << "point " << i;
        ASSERT_EQ(c.intensity[i], static_cast<float>(cols[ii].values[i])) << "point " << i;
    }
}
}  // namespace

TEST(PcdReader, RoundTripEveryEncodingAndType)
{
    TempDir dir;
    const struct
    {
        ScalarType type;
        double lo, hi;
    } types[] = {{ScalarType::Int8, -128, 127},    {ScalarType::UInt8, 0, 255},    {ScalarType::Int16, -3e4, 3e4},
                 {ScalarType::UInt16, 0, 65535},   {ScalarType::Int32, -1e9, 1e9}, {ScalarType::UInt32, 0, 4e9},
                 {ScalarType::Int64, -1e12, 1e12}, {ScalarType::UInt64, 0, 1e12},  {ScalarType::Float32, 0, 1},
                 {ScalarType::Float64, 0, 300}};
    uint32_t seed = 1;
    for (const char* data : kDataEncodings)
        for (const ScalarType coord : {ScalarType::Float32, ScalarType::Float64})
            for (const auto& t : types)
            {
                SCOPED_TRACE(std::string(data) + " intensity size " + std::to_string(detail::sizeOf(t.type)));
                const auto cols = makeColumns(300, coord, "intensity", t.type, t.lo, t.hi, seed++);
                const std::string path = dir.file("cloud.pcd");
                writePcd(path, data, cols);
                const RawCloud c = readPcd(path);
                EXPECT_EQ(c.encoding, data);
                expectSameCloud(c, cols, "intensity");
            }
}

TEST(PcdReader, CountsPaddingAndOtherFieldsAreSkipped)
{
    TempDir dir;
    for (const char* data : kDataEncodings)
    {
        SCOPED_TRACE(data);
        std::mt19937 rng(3);
        auto cols = makeColumns(123, ScalarType::Float32, "i", ScalarType::UInt8, 0, 255, 4);
        // Fields in an unusual order, a padding field, a COUNT > 1 field (first element is the value).
        cols.insert(cols.begin(), Column{"_", ScalarType::UInt8, std::vector<double>(123, 0.0), 3});
        cols.insert(cols.begin() + 2,
                    Column{"normal", ScalarType::Float32, randomValues(123, ScalarType::Float32, -1, 1, rng), 3});
        cols[3].count = 2;  // y, with a decoy second element
        cols.push_back({"ring", ScalarType::UInt16, randomValues(123, ScalarType::UInt16, 0, 63, rng)});
        const std::string path = dir.file("layout.pcd");
        writePcd(path, data, cols);
        expectSameCloud(readPcd(path), cols, "i");
    }
}

TEST(PcdReader, IntensityFieldNames)
{
    TempDir dir;
    const std::string path = dir.file("names.pcd");
    for (const std::string name : {"intensity", "reflectivity", "i", "reflectance", "scalar_Intensity"})
    {
        const auto cols = makeColumns(10, ScalarType::Float32, name, ScalarType::Float32, 0, 1, 8);
        writePcd(path, "binary", cols);
        expectSameCloud(readPcd(path), cols, name);
    }
    // intensity wins over i when both are present.
    std::mt19937 rng(1);
    auto cols = makeColumns(10, ScalarType::Float32, "i", ScalarType::Float32, 0, 1, 9);
    cols.push_back({"intensity", ScalarType::UInt8, randomValues(10, ScalarType::UInt8, 0, 255, rng)});
    writePcd(path, "ascii", cols);
    expectSameCloud(readPcd(path), cols, "intensity");
}

TEST(PcdReader, OrganisedCloudUsesWidthTimesHeight)
{
    TempDir dir;
    const std::string path = dir.file("organised.pcd");
    std::ofstream(path) << "# .PCD v.7\nVERSION .7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\n"
                           "WIDTH 2\nHEIGHT 2\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA ascii\n"
                           "1 2 3 0.5\n4 5 6 0.25\n7 8 9 1\n10 11 12 0\n";
    const RawCloud c = readPcd(path);
    ASSERT_EQ(c.size(), 4u);
    EXPECT_FLOAT_EQ(c.x[3], 10.f);
    EXPECT_FLOAT_EQ(c.intensity[1], 0.25f);
}

TEST(PcdReader, BadInputNamesTheFile)
{
    TempDir dir;
    const auto cols = makeColumns(200, ScalarType::Float32, "intensity", ScalarType::Float32, 0, 1, 2);
    const std::string missing = dir.file("missing.pcd");
    expectInputError([&] { readPcd(missing); }, missing, "not found");

    const std::string no_i = dir.file("no_i.pcd");
    writePcd(no_i, "binary", {cols[0], cols[1], cols[2]});
    expectInputError([&] { readPcd(no_i); }, no_i, "no intensity field");

    for (const char* data : kDataEncodings)
    {
        const std::string cut = dir.file(std::string("cut_") + data + ".pcd");
        writePcd(cut, data, cols, 40);
        expectInputError([&] { readPcd(cut); }, cut, "truncated");
    }
    const std::string corrupt = dir.file("corrupt.pcd");
    writePcd(corrupt, "binary_compressed", cols, 0, true);
    expectInputError([&] { readPcd(corrupt); }, corrupt, "corrupt LZF");

    auto nan_cols = cols;
    nan_cols[0].values[77] = std::nan("");
    for (const char* data : kDataEncodings)
    {
        const std::string nan_path = dir.file(std::string("nan_") + data + ".pcd");
        writePcd(nan_path, data, nan_cols);
        expectInputError([&] { readCloud(nan_path); }, nan_path, "point 77 has a non-finite");
    }
    const std::string empty = dir.file("empty.pcd");
    writePcd(empty, "binary", makeColumns(0, ScalarType::Float32, "intensity", ScalarType::Float32, 0, 1, 1));
    expectInputError([&] { readCloud(empty); }, empty, "empty");

    const std::string no_data = dir.file("no_data.pcd");
    std::ofstream(no_data) << "VERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\n";
    expectInputError([&] { readPcd(no_data); }, no_data, "no DATA line");
    const std::string bad_type = dir.file("bad_type.pcd");
    std::ofstream(bad_type) << "VERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 3\nTYPE F F F F\nWIDTH 1\n"
                               "POINTS 1\nDATA ascii\n1 2 3 4\n";
    expectInputError([&] { readPcd(bad_type); }, bad_type, "unsupported TYPE/SIZE");
    const std::string bad_points = dir.file("bad_points.pcd");
    std::ofstream(bad_points) << "VERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\nWIDTH 3\n"
                                 "HEIGHT 1\nPOINTS 2\nDATA ascii\n1 2 3 4\n1 2 3 4\n";
    expectInputError([&] { readPcd(bad_points); }, bad_points, "WIDTH * HEIGHT");
}
