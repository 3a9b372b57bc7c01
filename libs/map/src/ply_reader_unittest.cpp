#include <gtest/gtest.h>

#include <cmath>
#include <quasiloc/map/map_import.h>

#include "test_cloud_files.h"

using namespace quasiloc::map;
using namespace quasiloc::map::test;

namespace
{
/** x y z (coord_type) and an intensity column, n random points. */
std::vector<Column> makeColumns(size_t n, ScalarType coord_type, const std::string& iname, ScalarType itype, double ilo,
                                double ihi, uint32_t seed)
{
    std::mt19937 rng(seed);
    std::vector<Column> cols;
    for (const char* axis : {"x", "y", "z"})
        cols.push_back({axis, coord_type, randomValues(n, coord_type, -50, 50, rng)});
    cols.push_back({iname, itype, randomValues(n, itype, ilo, ihi, rng)});
    return cols;
}

void expectSameCloud(const RawCloud& c, const std::vector<Column>& cols, int intensity_col = 3)
{
    ASSERT_EQ(c.size(), cols[0].values.size());
    for (size_t i = 0; i < c.size(); ++i)
    {
        ASSERT_EQ(c.x[i], static_cast<float>(cols[0].values[i])) << "point " << i;
        ASSERT_EQ(c.y[i], static_cast<float>(cols[1].values[i])) << "point " << i;
        ASSERT_EQ(c.z[i], static_cast<float>(cols[2].values[i])) << "point " << i;
        ASSERT_EQ(c.intensity[i], static_cast<float>(cols[intensity_col].values[i])) << "point " << i;
    }
}

struct TypeCase
{
    ScalarType type;
    double lo, hi;
};
const TypeCase kIntensityTypes[] = {{ScalarType::Int8, -128, 127},      {ScalarType::UInt8, 0, 255},
                                    {ScalarType::Int16, -32768, 32767}, {ScalarType::UInt16, 0, 65535},
                                    {ScalarType::Int32, -1e9, 1e9},     {ScalarType::UInt32, 0, 4e9},
                                    {ScalarType::Float32, 0, 1},        {ScalarType::Float64, -1e6, 1e6}};
const char* kEncodings[] = {"ascii", "binary_little_endian", "binary_big_endian"};
}  // namespace

TEST(PlyReader, RoundTripEveryEncodingAndIntensityType)
{
    TempDir dir;
    uint32_t seed = 1;
    for (const char* enc : kEncodings)
        for (const ScalarType coord : {ScalarType::Float32, ScalarType::Float64})
            for (const TypeCase& tc : kIntensityTypes)
            {
                SCOPED_TRACE(std::string(enc) + " intensity type " + plyTypeName(tc.type));
                const auto cols = makeColumns(57, coord, "intensity", tc.type, tc.lo, tc.hi, seed++);
                const std::string path = dir.file("cloud.ply");
                writePly(path, enc, cols);
                const RawCloud c = readPly(path);
                EXPECT_EQ(c.encoding, enc);
                EXPECT_EQ(c.intensity_field, "intensity");
                expectSameCloud(c, cols);
            }
}

TEST(PlyReader, TypeAliasesAreAccepted)
{
    TempDir dir;
    const std::string path = dir.file("aliases.ply");
    std::ofstream(path) << "ply\nformat ascii 1.0\nelement vertex 2\nproperty float32 x\nproperty float64 y\n"
                           "property int16 z\nproperty uint8 reflectivity\nproperty int8 a\nproperty uint16 b\n"
                           "property int32 c\nproperty uint32 d\nend_header\n"
                           "1.5 2.25 -3 200 -1 2 3 4\n-1 0.5 7 13 1 2 3 4\n";
    const RawCloud c = readPly(path);
    ASSERT_EQ(c.size(), 2u);
    EXPECT_EQ(c.intensity_field, "reflectivity");
    EXPECT_FLOAT_EQ(c.x[0], 1.5f);
    EXPECT_FLOAT_EQ(c.y[0], 2.25f);
    EXPECT_FLOAT_EQ(c.z[0], -3.f);
    EXPECT_FLOAT_EQ(c.intensity[0], 200.f);
    EXPECT_FLOAT_EQ(c.intensity[1], 13.f);
}

TEST(PlyReader, SkipsOtherPropertiesListsAndElements)
{
    TempDir dir;
    for (const char* enc : kEncodings)
    {
        SCOPED_TRACE(enc);
        std::mt19937 rng(7);
        auto cols = makeColumns(40, ScalarType::Float32, "intensity", ScalarType::UInt16, 0, 65535, 3);
        // Extra per-vertex properties before and after the ones we want.
        cols.insert(cols.begin() + 3,
                    Column{"nx", ScalarType::Float64, randomValues(40, ScalarType::Float64, -1, 1, rng)});
        cols.push_back({"red", ScalarType::UInt8, randomValues(40, ScalarType::UInt8, 0, 255, rng)});
        const std::string path = dir.file("extras.ply");
        PlyExtras extras;
        extras.element_before = extras.list_in_vertex = extras.element_after = true;
        writePly(path, enc, cols, extras);
        expectSameCloud(readPly(path), cols, 4);
    }
}

TEST(PlyReader, PicksTheBestIntensityLikeProperty)
{
    TempDir dir;
    const std::string path = dir.file("names.ply");
    struct Case
    {
        std::vector<std::string> names;
        std::string expected;
    };
    const Case cases[] = {{{"scalar_Scalar_field", "Intensity"}, "Intensity"},
                          {{"scalar_intensity", "reflectance"}, "reflectance"},
                          {{"scalar_Height", "scalar_Intensity"}, "scalar_Intensity"},
                          {{"scalar_Scalar_field"}, "scalar_Scalar_field"},
                          {{"scalar_field"}, "scalar_field"},
                          {{"scalar_Return"}, "scalar_Return"},
                          {{"reflectivity", "scalar_field"}, "reflectivity"}};
    for (const Case& cs : cases)
    {
        std::mt19937 rng(11);
        auto cols = makeColumns(5, ScalarType::Float32, cs.names[0], ScalarType::Float32, 0, 1, 5);
        for (size_t k = 1; k < cs.names.size(); ++k)
            cols.push_back({cs.names[k], ScalarType::UInt8, randomValues(5, ScalarType::UInt8, 0, 255, rng)});
        writePly(path, "binary_little_endian", cols);
        const RawCloud c = readPly(path);
        EXPECT_EQ(c.intensity_field, cs.expected);
        const size_t col = cs.expected == cs.names[0] ? 3 : 4;
        expectSameCloud(c, cols, static_cast<int>(col));
    }
}

TEST(PlyReader, BadInputNamesTheFile)
{
    TempDir dir;
    const auto cols = makeColumns(20, ScalarType::Float32, "intensity", ScalarType::Float32, 0, 1, 9);
    const std::string missing = dir.file("missing.ply");
    expectInputError([&] { readPly(missing); }, missing, "not found");

    const std::string no_i = dir.file("no_intensity.ply");
    writePly(no_i, "binary_little_endian", {cols[0], cols[1], cols[2]});
    expectInputError([&] { readPly(no_i); }, no_i, "no intensity field");

    for (const char* enc : {"binary_little_endian", "binary_big_endian"})
    {
        const std::string cut = dir.file(std::string("truncated_") + enc + ".ply");
        writePly(cut, enc, cols, {}, 5);
        expectInputError([&] { readPly(cut); }, cut, "truncated");
    }
    const std::string cut_ascii = dir.file("truncated_ascii.ply");
    writePly(cut_ascii, "ascii", cols, {}, 30);
    expectInputError([&] { readPly(cut_ascii); }, cut_ascii, "truncated");

    auto nan_cols = cols;
    nan_cols[1].values[13] = std::nan("");
    const std::string nan_path = dir.file("nan.ply");
    writePly(nan_path, "binary_little_endian", nan_cols);
    expectInputError([&] { readCloud(nan_path); }, nan_path, "point 13 has a non-finite");
    auto inf_cols = cols;
    inf_cols[2].values[4] = INFINITY;
    writePly(nan_path, "ascii", inf_cols);
    expectInputError([&] { readCloud(nan_path); }, nan_path, "point 4 has a non-finite");

    const std::string empty = dir.file("empty.ply");
    writePly(empty, "binary_little_endian",
             makeColumns(0, ScalarType::Float32, "intensity", ScalarType::Float32, 0, 1, 1));
    EXPECT_EQ(readPly(empty).size(), 0u);
    expectInputError([&] { readCloud(empty); }, empty, "empty");

    const std::string not_ply = dir.file("not.ply");
    std::ofstream(not_ply) << "hello\nworld\n";
    expectInputError([&] { readPly(not_ply); }, not_ply, "not a PLY file");
    const std::string no_end = dir.file("no_end.ply");
    std::ofstream(no_end) << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n";
    expectInputError([&] { readPly(no_end); }, no_end, "end_header");
    const std::string bad_type = dir.file("bad_type.ply");
    std::ofstream(bad_type) << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n";
    expectInputError([&] { readPly(bad_type); }, bad_type, "unknown PLY type");
    const std::string bad_num = dir.file("bad_num.ply");
    std::ofstream(bad_num) << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                              "property float z\nproperty float intensity\nend_header\n1 2 x3 0.5\n";
    expectInputError([&] { readPly(bad_num); }, bad_num, "not a number");
}
