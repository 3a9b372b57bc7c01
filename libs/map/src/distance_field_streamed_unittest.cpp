// The streamed DistanceField: the sparse field's values bit for bit (before and after eviction), its tile cache on
// disk (read back exactly, a stale header refused, a corrupt tile rebuilt), concurrent queries.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <quasiloc/core/error.h>
#include <quasiloc/map/distance_field.h>
#include <random>
#include <thread>

using namespace quasiloc;

namespace
{
/** Ground over 14 x 10 m (8 cm spacing, gently sloped), a wall and a pole: several tiles at 4 cm. */
map::LidarMap testMap()
{
    map::LidarMap m;
    for (float x = -7; x <= 7.0001f; x += 0.08f)
        for (float y = -5; y <= 5.0001f; y += 0.08f) m.addPoint(x, y, 0.03f * x + 0.02f * y, 0.5f);
    for (float y = -5; y <= 5.0001f; y += 0.05f)
        for (float z = 0; z <= 3.0001f; z += 0.05f) m.addPoint(4.2f, y, z, 0.5f);
    for (float z = 0; z <= 4.0001f; z += 0.03f) m.addPoint(-2.5f, 1.5f, z, 0.2f);
    return m;
}

map::DistanceFieldOptions options(map::DistanceFieldLayout layout)
{
    map::DistanceFieldOptions o;
    o.layout = layout;
    o.voxel_m = 0.04;
    o.max_distance_m = 0.3;
    o.margin_m = 1.0;
    return o;
}

/** The number of voxels where a and b differ (every voxel of the grid, a tile of 128^3 voxels after another, the
 *  order in which a streamed field with a small budget does not rebuild a tile per row). */
size_t differingVoxels(const map::DistanceField& a, const map::DistanceField& b)
{
    const Eigen::Vector3i n = a.dimensions();
    constexpr int kTile = 128;
    size_t differing = 0;
    for (int tk = 0; tk < n.z(); tk += kTile)
        for (int tj = 0; tj < n.y(); tj += kTile)
            for (int ti = 0; ti < n.x(); ti += kTile)
                for (int k = tk; k < std::min(n.z(), tk + kTile); ++k)
                    for (int j = tj; j < std::min(n.y(), tj + kTile); ++j)
                        for (int i = ti; i < std::min(n.x(), ti + kTile); ++i)
                            differing += a.voxel(i, j, k) != b.voxel(i, j, k);
    return differing;
}

std::string freshFolder(const std::string& name)
{
    const std::string dir = ::testing::TempDir() + "/" + name;
    std::filesystem::remove_all(dir);
    return dir;
}
}  // namespace

TEST(StreamedDistanceField, HoldsTheSparseValuesBitForBitBeforeAndAfterEviction)
{
    const map::LidarMap m = testMap();
    const map::DistanceField sparse = map::DistanceField::build(m, options(map::DistanceFieldLayout::Sparse));
    map::DistanceFieldOptions o = options(map::DistanceFieldLayout::Streamed);
    o.memory_budget_mb = 2;  // a few tiles: the sweep below evicts and rebuilds
    const map::DistanceField streamed = map::DistanceField::build(m, o);
    ASSERT_TRUE(streamed.streamed());
    ASSERT_EQ(streamed.dimensions(), sparse.dimensions());
    EXPECT_EQ(differingVoxels(sparse, streamed), 0u);
    const map::DistanceField::StreamStats first = streamed.streamStats();
    EXPECT_GT(first.evicted, 0u) << "the budget did not evict: the test does not test eviction";
    EXPECT_LE(streamed.memoryBytes(), size_t(8) << 20);  // the budget, and the 8 tiles inserted last
    // Sweep again: the evicted tiles are rebuilt with the same values.
    EXPECT_EQ(differingVoxels(sparse, streamed), 0u);
    EXPECT_GT(streamed.streamStats().built, first.built);
    // Queries (a cell can span tiles) with the default budget: in random order, 2 MB would rebuild a tile per query.
    o.memory_budget_mb = map::DistanceFieldOptions().memory_budget_mb;
    const map::DistanceField queried = map::DistanceField::build(m, o);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-8, 8);
    for (int q = 0; q < 5000; ++q)
    {
        const Eigen::Vector3f p(u(rng), u(rng) * 0.7f, u(rng) * 0.3f + 1.0f);
        Eigen::Vector3f gs, gt;
        ASSERT_EQ(sparse.distance(p, gs), queried.distance(p, gt)) << p.transpose();
        ASSERT_EQ(gs, gt) << p.transpose();
    }
}

TEST(StreamedDistanceField, FocusReadiesTheTilesAroundTheCameraAndQueriesRunConcurrently)
{
    const map::LidarMap m = testMap();
    const map::DistanceField sparse = map::DistanceField::build(m, options(map::DistanceFieldLayout::Sparse));
    map::DistanceFieldOptions o = options(map::DistanceFieldLayout::Streamed);
    o.focus_radius_m = 3;
    const map::DistanceField streamed = map::DistanceField::build(m, o);
    EXPECT_EQ(streamed.streamStats().built, 0u);
    streamed.focus({0, 0, 1});
    streamed.waitForFocus();
    const size_t readied = streamed.streamStats().built;
    EXPECT_GT(readied, 0u);
    // Queries within the radius find their tiles built; two threads query at once, and all values are the sparse's.
    std::vector<Eigen::Vector3f> near, far;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.5f, 1.5f), v(-7, 7);
    for (int q = 0; q < 4000; ++q) near.emplace_back(u(rng), u(rng), 0.5f + 0.3f * u(rng));
    for (int q = 0; q < 4000; ++q) far.emplace_back(v(rng), 0.7f * v(rng), 0.5f + 0.3f * u(rng));
    size_t wrong[2] = {0, 0};
    std::thread other([&] {
        for (const auto& p : far) wrong[1] += streamed.distance(p) != sparse.distance(p);
    });
    for (const auto& p : near) wrong[0] += streamed.distance(p) != sparse.distance(p);
    other.join();
    EXPECT_EQ(wrong[0] + wrong[1], 0u);
    EXPECT_GT(streamed.streamStats().synchronous, 0u) << "the far queries should have built tiles themselves";
}

TEST(StreamedDistanceField, TileCacheIsReadBackExactlyAndWrittenThrough)
{
    const map::LidarMap m = testMap();
    const std::string dir = freshFolder("streamed_field_cache");
    const map::DistanceField sparse = map::DistanceField::build(m, options(map::DistanceFieldLayout::Sparse));
    map::DistanceFieldOptions o = options(map::DistanceFieldLayout::Streamed);
    o.tile_cache = dir;
    {
        const map::DistanceField writer = map::DistanceField::build(m, o);
        EXPECT_GT(writer.writeAllTiles(), 0u);
    }
    const map::DistanceField reader = map::DistanceField::build(m, o);
    EXPECT_EQ(differingVoxels(sparse, reader), 0u);
    const map::DistanceField::StreamStats s = reader.streamStats();
    EXPECT_EQ(s.built, 0u) << "a complete cache builds nothing";
    EXPECT_GT(s.read, 0u);
    EXPECT_EQ(s.rebuilt_corrupt, 0u);
    // Write-through: a field on an empty cache folder writes the tiles it builds; the next one reads them.
    const std::string lazy_dir = freshFolder("streamed_field_lazy");
    o.tile_cache = lazy_dir;
    size_t built = 0;
    {
        const map::DistanceField first = map::DistanceField::build(m, o);
        EXPECT_EQ(first.distance({0, 0, 0.2f}), sparse.distance({0, 0, 0.2f}));
        built = first.streamStats().written;
        EXPECT_GT(built, 0u);
    }
    const map::DistanceField second = map::DistanceField::build(m, o);
    EXPECT_EQ(second.distance({0, 0, 0.2f}), sparse.distance({0, 0, 0.2f}));
    EXPECT_EQ(second.streamStats().read, built);
}

TEST(StreamedDistanceField, AStaleCacheIsAnErrorNamingItsHeaderAndACorruptTileIsRebuilt)
{
    const map::LidarMap m = testMap();
    const std::string dir = freshFolder("streamed_field_bad_cache");
    map::DistanceFieldOptions o = options(map::DistanceFieldLayout::Streamed);
    o.tile_cache = dir;
    map::DistanceField::build(m, o).writeAllTiles();
    // Another truncation, then another map: the header says so, and nothing is read.
    for (int change = 0; change < 2; ++change)
    {
        map::DistanceFieldOptions other = o;
        map::LidarMap other_map = testMap();
        if (change == 0) other.max_distance_m = 0.4;
        if (change == 1) other_map.addPoint(0.5f, 0.5f, 1.0f, 0.5f);
        try
        {
            map::DistanceField::build(other_map, other, "campus.map");
            FAIL() << "a stale cache was accepted";
        }
        catch (const core::InputError& e)
        {
            const std::string what = e.what();
            EXPECT_NE(what.find(dir + "/header.txt"), std::string::npos) << what;
            EXPECT_NE(what.find(change == 0 ? "max_distance_m" : "map_"), std::string::npos) << what;
        }
    }
    // A tile file cut short and another with one value changed: both rebuilt from the points, never used.
    std::vector<std::string> tiles;
    for (const auto& e : std::filesystem::directory_iterator(dir))
        if (e.path().filename().string().rfind("t_", 0) == 0) tiles.push_back(e.path().string());
    ASSERT_GE(tiles.size(), 2u);
    std::filesystem::resize_file(tiles[0], std::filesystem::file_size(tiles[0]) / 2);
    {
        std::fstream f(tiles[1], std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(200);
        f.put('\x7f');
    }
    const map::DistanceField sparse = map::DistanceField::build(m, options(map::DistanceFieldLayout::Sparse));
    const map::DistanceField reader = map::DistanceField::build(m, o);
    EXPECT_EQ(differingVoxels(sparse, reader), 0u);
    EXPECT_EQ(reader.streamStats().rebuilt_corrupt, 2u);
    EXPECT_EQ(reader.streamStats().built, 2u);
    // The rebuilt tiles were rewritten: a third field reads every tile.
    const map::DistanceField again = map::DistanceField::build(m, o);
    EXPECT_EQ(differingVoxels(sparse, again), 0u);
    EXPECT_EQ(again.streamStats().rebuilt_corrupt, 0u);
    EXPECT_EQ(again.streamStats().built, 0u);
}
