// DistanceField: the transform against brute force, the interpolant's gradient against numeric differences,
// truncation, and the size guard.
#include <gtest/gtest.h>

#include <limits>
#include <quasiloc/core/error.h>
#include <quasiloc/map/distance_field.h>
#include <random>

using namespace quasiloc;

namespace
{
/** A floor (z = 0, 2 x 2 m, 2 cm spacing), a wall (x = 1) and three isolated points. */
map::LidarMap testMap()
{
    map::LidarMap m;
    for (float x = -1; x <= 1.0001f; x += 0.02f)
        for (float y = -1; y <= 1.0001f; y += 0.02f) m.addPoint(x, y, 0, 0.5f);
    for (float y = -1; y <= 1.0001f; y += 0.02f)
        for (float z = 0; z <= 1.0001f; z += 0.02f) m.addPoint(1, y, z, 0.5f);
    m.addPoint(-0.5f, 0.3f, 0.7f, 0.1f);
    m.addPoint(0.2f, -0.4f, 0.45f, 0.1f);
    m.addPoint(-0.9f, -0.9f, 1.1f, 0.1f);
    return m;
}

float bruteForce(const map::LidarMap& m, const Eigen::Vector3f& p)
{
    float best = std::numeric_limits<float>::max();
    for (size_t i = 0; i < m.size(); ++i) best = std::min(best, (m.point(i) - p).norm());
    return best;
}
}  // namespace

TEST(DistanceField, MatchesBruteForceWithinHalfAVoxel)
{
    for (const auto layout : {map::DistanceFieldLayout::Dense, map::DistanceFieldLayout::Sparse})
    {
        SCOPED_TRACE(layout == map::DistanceFieldLayout::Dense ? "dense" : "sparse");
        const map::LidarMap m = testMap();
        map::DistanceFieldOptions o;
        o.layout = layout;
        o.voxel_m = 0.04;
        o.margin_m = 0.3;
        o.max_distance_m = 0.6;
        const map::DistanceField f = map::DistanceField::build(m, o);
        std::mt19937 rng(3);
        std::uniform_real_distribution<float> u(-1.2f, 1.2f);
        double worst = 0;
        for (int n = 0; n < 2000; ++n)
        {
            const Eigen::Vector3f p(u(rng), u(rng), 0.6f * u(rng) + 0.6f);
            const float truth = std::min(0.6f, bruteForce(m, p));
            // Voxel centres stand for the points (<= half a diagonal away) and trilinear interpolation of a distance
            // adds at most about another half diagonal near a surface.
            worst = std::max(worst, double(std::abs(f.distance(p) - truth)));
        }
        EXPECT_LT(worst, 0.04 * std::sqrt(3.0));
        // Farther than max_distance_m: truncated; outside the grid: the truncation value.
        EXPECT_FLOAT_EQ(f.distance(Eigen::Vector3f(-0.2f, 0.9f, 1.25f)), 0.6f);
        EXPECT_GT(bruteForce(m, {-0.2f, 0.9f, 1.25f}), 0.6f + 0.04f);
        EXPECT_FLOAT_EQ(f.distance(Eigen::Vector3f(50, 0, 0)), 0.6f);
        EXPECT_EQ(f.sparse(), layout == map::DistanceFieldLayout::Sparse);
    }
}

TEST(DistanceField, GradientIsTheInterpolantsDerivative)
{
    for (const auto layout : {map::DistanceFieldLayout::Dense, map::DistanceFieldLayout::Sparse})
    {
        SCOPED_TRACE(layout == map::DistanceFieldLayout::Dense ? "dense" : "sparse");
        const map::LidarMap m = testMap();
        map::DistanceFieldOptions o;
        o.layout = layout;
        o.voxel_m = 0.05;
        const map::DistanceField f = map::DistanceField::build(m, o);
        std::mt19937 rng(5);
        std::uniform_int_distribution<int> cell(5, 35);
        std::uniform_real_distribution<float> inside(0.1f, 0.9f);
        for (int n = 0; n < 200; ++n)
        {
            // Inside a cell: the trilinear interpolant is smooth there (its derivative jumps across cell faces).
            const Eigen::Vector3f p =
                f.origin() + 0.05f * Eigen::Vector3f(float(cell(rng)) + inside(rng), float(cell(rng)) + inside(rng),
                                                     float(cell(rng)) + inside(rng));
            Eigen::Vector3f g;
            f.distance(p, g);
            for (int a = 0; a < 3; ++a)
            {
                const float h = 1e-3f;
                Eigen::Vector3f e = Eigen::Vector3f::Zero();
                e[a] = h;
                const float numeric = (f.distance(p + e) - f.distance(p - e)) / (2 * h);
                EXPECT_NEAR(g[a], numeric, 0.05) << "axis " << a << " at " << p.transpose();
            }
        }
        // Above the floor and away from the rest, the field rises along +z.
        Eigen::Vector3f g;
        f.distance(Eigen::Vector3f(-0.2f, 0.6f, 0.2f), g);
        EXPECT_NEAR(g.z(), 1.0, 0.1);
        EXPECT_NEAR(g.head<2>().norm(), 0.0, 0.1);
    }
}

TEST(DistanceField, RejectsAGridAboveTheLimitAndAnEmptyMap)
{
    map::DistanceFieldOptions o;
    o.voxel_m = 0.001;
    o.max_voxels = 1'000'000;
    o.layout = map::DistanceFieldLayout::Dense;
    try
    {
        map::DistanceField::build(testMap(), o, "room.map");
        FAIL() << "no error for a grid above max_voxels";
    }
    catch (const core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("room.map"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("max_voxels"), std::string::npos) << e.what();
    }
    EXPECT_THROW(map::DistanceField::build(map::LidarMap(), map::DistanceFieldOptions(), "empty.map"),
                 core::InputError);
    o = map::DistanceFieldOptions();
    o.voxel_m = 0;
    EXPECT_THROW(map::DistanceField::build(testMap(), o), core::InputError);
}

TEST(DistanceField, SparseFieldHoldsTheDenseValuesBitForBitWithLessMemory)
{
    const map::LidarMap m = testMap();
    for (double voxel : {0.04, 0.03})
    {
        map::DistanceFieldOptions o;
        o.voxel_m = voxel;
        o.max_distance_m = 0.3;
        o.margin_m = 1.5;  // room around the map that the sparse field does not store
        o.layout = map::DistanceFieldLayout::Dense;
        const map::DistanceField dense = map::DistanceField::build(m, o);
        o.layout = map::DistanceFieldLayout::Sparse;
        const map::DistanceField sparse = map::DistanceField::build(m, o);
        ASSERT_TRUE(sparse.sparse());
        ASSERT_EQ(sparse.dimensions(), dense.dimensions());
        const Eigen::Vector3i n = dense.dimensions();
        size_t differing = 0;
        for (int k = 0; k < n.z(); ++k)
            for (int j = 0; j < n.y(); ++j)
                for (int i = 0; i < n.x(); ++i) differing += dense.voxel(i, j, k) != sparse.voxel(i, j, k);
        EXPECT_EQ(differing, 0u) << "voxel " << voxel;
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> u(-2.4f, 2.4f);
        for (int q = 0; q < 2000; ++q)
        {
            const Eigen::Vector3f p(u(rng), u(rng), u(rng) * 0.5f + 0.5f);
            Eigen::Vector3f gd, gs;
            ASSERT_EQ(dense.distance(p, gd), sparse.distance(p, gs)) << p.transpose();
            ASSERT_EQ(gd, gs) << p.transpose();
        }
        EXPECT_LT(sparse.memoryBytes(), dense.memoryBytes() / 2)
            << sparse.allocatedBricks() << " bricks, " << sparse.memoryBytes() << " against " << dense.memoryBytes();
    }
}

TEST(DistanceField, AutoLayoutIsDenseForARoomAndSparseBeyondTheLimit)
{
    map::DistanceFieldOptions o;
    EXPECT_FALSE(map::DistanceField::build(testMap(), o).sparse());
    o.dense_max_voxels = 1000;
    EXPECT_TRUE(map::DistanceField::build(testMap(), o).sparse());
}
