// The sharded database build: shards rendered separately and merged save the same bytes as a
// single-process build; a shard is a compact, connected tile of nearly equal size; the merge names a missing shard,
// a shard of another map, a shard built with other options and a copied shard file, and reads nothing half-written.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <quasiloc/core/error.h>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/quasi/synthetic_scene.h>
#include <quasiloc/reloc/database_builder.h>
#include <quasiloc/reloc/database_shard.h>
#include <set>
#include <string>

using namespace quasiloc;

namespace
{
namespace fs = std::filesystem;
const std::string kShared = QUASILOC_SHARED_DIR;

std::string freshDir(const std::string& name)
{
    const std::string dir = testing::TempDir() + "/shard_" + name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::string fileBytes(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

core::CameraModel testCamera()
{
    const std::string calib = kShared + "/data/euroc/calib/";
    return core::StereoRig::fromEuroc(calib + "cam0_sensor.yaml", calib + "cam1_sensor.yaml").left;
}

reloc::DatabaseBuildConfig smallConfig()
{
    reloc::DatabaseBuildConfig c;
    c.sampling.grid_spacing_m = 1.5;
    c.sampling.heights_m = {1.3};
    c.sampling.pitches_deg = {-10};
    c.sampling.num_headings = 4;
    c.build.store_lines = true;  // the shard file carries every part of a view
    c.build.min_lifted = 0;
    c.build.threads = 2;
    c.vocabulary.branching = 6;
    c.vocabulary.depth = 3;
    return c;
}

/** A shard with no views, as the merge's header checks see it. */
reloc::DatabaseShard headerShard(reloc::ShardSelection s, uint64_t sampled, const std::string& options)
{
    reloc::DatabaseShard shard;
    shard.selection = s;
    shard.map = {1234, 0xabcdef};
    shard.map_file = "room.map";
    shard.options = options;
    shard.sampled_views = sampled;
    shard.rendered = reloc::shardSize(sampled, s);
    shard.dropped_valid = shard.rendered;
    shard.camera = testCamera();
    return shard;
}

reloc::ShardExpectation expectation(int count, const std::string& options)
{
    reloc::ShardExpectation e;
    e.count = count;
    e.map = {1234, 0xabcdef};
    e.map_file = "room.map";
    e.options = options;
    e.config_name = "build.ini";
    return e;
}

/** The InputError message of `f`, or "" when it does not throw one. */
template <class F>
std::string inputError(F&& f)
{
    try
    {
        f();
    }
    catch (const core::InputError& e)
    {
        return e.what();
    }
    return "";
}
}  // namespace

TEST(DatabaseShard, MergedShardsSaveTheSameBytesAsASingleProcessBuild)
{
    const map::LidarMap room = quasi::makeSyntheticRoom(300000);
    const core::CameraModel camera = testCamera();
    const reloc::DatabaseBuildConfig config = smallConfig();
    const std::string dir = freshDir("equality");
    const std::string map_file = dir + "/room.map";
    room.save(map_file);

    reloc::DatabaseBuildStats whole_stats;
    reloc::Database whole = reloc::buildDatabase(room, camera, config, &whole_stats);
    whole.map_file = map_file;  // the program records the map's path, the same in both
    whole.save(dir + "/whole.qdb");
    ASSERT_GT(whole.views.size(), 20u);
    ASSERT_LT(whole_stats.kept, whole_stats.rendered);  // views dropped (80 -> 64): the ids are renumbered over gaps

    // Three shards (the views do not divide evenly), each with its own worker count, saved and read back.
    const int n = 3;
    const std::string output = dir + "/merged.qdb";
    size_t rendered = 0;
    for (int i = 0; i < n; ++i)
    {
        reloc::DatabaseBuildConfig c = config;
        c.build.threads = 1 + i % 2;
        reloc::DatabaseShard s = reloc::buildDatabaseShard(room, camera, c, {i, n});
        EXPECT_EQ(s.sampled_views, whole_stats.rendered);
        EXPECT_LE(s.rendered, whole_stats.rendered / n + 1);
        EXPECT_GE(s.rendered, whole_stats.rendered / n);
        rendered += s.rendered;
        s.map = reloc::MapIdentity::ofFile(map_file);
        s.map_file = map_file;
        s.save(reloc::shardPath(output, {i, n}));
    }
    EXPECT_EQ(rendered, whole_stats.rendered);
    reloc::ShardExpectation expect;
    expect.count = n;
    expect.map = reloc::MapIdentity::ofFile(map_file);
    expect.map_file = map_file;
    expect.options = reloc::resultOptionsText(config, camera);
    expect.config_name = "test";
    reloc::DatabaseBuildStats merged_stats;
    reloc::Database merged =
        reloc::finishDatabase(reloc::loadShardsForMerge(output, expect), config.vocabulary, &merged_stats);
    merged.map_file = map_file;
    merged.save(output);
    EXPECT_EQ(merged_stats.kept, whole_stats.kept);
    EXPECT_EQ(merged_stats.dropped_valid + merged_stats.dropped_lifted,
              whole_stats.dropped_valid + whole_stats.dropped_lifted);

    const std::string a = fileBytes(dir + "/whole.qdb"), b = fileBytes(output);
    ASSERT_FALSE(a.empty());
    EXPECT_TRUE(a == b) << "the merged database differs from the single-process one (" << a.size() << " vs " << b.size()
                        << " bytes)";
    fs::remove_all(dir);
}

TEST(DatabaseShard, ShardsAreConnectedCompactTilesOfNearlyEqualSize)
{
    // An 8 x 8 grid of positions, 3 views each: 4 shards are the 4 quadrants; 5 shards differ by one view at most.
    std::vector<mrpt::poses::CPose3D> poses;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x)
            for (int k = 0; k < 3; ++k) poses.push_back(reloc::viewPose(10 + 0.5 * x, -3 + 0.5 * y, 1.2, k, 0));
    std::set<size_t> seen;
    for (int i = 0; i < 4; ++i)
    {
        const auto views = reloc::shardViews(poses, 0.5, {i, 4});
        ASSERT_EQ(views.size(), poses.size() / 4);
        EXPECT_TRUE(std::is_sorted(views.begin(), views.end()));
        double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
        for (size_t v : views)
        {
            EXPECT_TRUE(seen.insert(v).second) << "view " << v << " in two shards";
            x0 = std::min(x0, poses[v].x());
            x1 = std::max(x1, poses[v].x());
            y0 = std::min(y0, poses[v].y());
            y1 = std::max(y1, poses[v].y());
        }
        EXPECT_NEAR(x1 - x0, 1.5, 1e-9) << "shard " << i << " is not a 4 x 4 quadrant";
        EXPECT_NEAR(y1 - y0, 1.5, 1e-9) << "shard " << i << " is not a 4 x 4 quadrant";
    }
    EXPECT_EQ(seen.size(), poses.size());
    size_t total = 0;
    for (int i = 0; i < 5; ++i)
    {
        const size_t size = reloc::shardViews(poses, 0.5, {i, 5}).size();
        EXPECT_EQ(size, reloc::shardSize(poses.size(), {i, 5}));
        EXPECT_TRUE(size == poses.size() / 5 || size == poses.size() / 5 + 1) << size;
        total += size;
    }
    EXPECT_EQ(total, poses.size());
    EXPECT_EQ(reloc::shardViews(poses, 0.5, {0, 1}).size(), poses.size());
    // Any cut of the order gives connected tiles (the Hilbert curve's consecutive cells are grid neighbours).
    for (int n : {3, 5, 7})
        for (int i = 0; i < n; ++i)
        {
            std::set<std::pair<int, int>> cells, reached;
            for (size_t v : reloc::shardViews(poses, 0.5, {i, n}))
                cells.insert({int(std::lround(poses[v].x() * 2)), int(std::lround(poses[v].y() * 2))});
            std::vector<std::pair<int, int>> todo{*cells.begin()};
            while (!todo.empty())
            {
                const auto c = todo.back();
                todo.pop_back();
                if (!cells.count(c) || !reached.insert(c).second) continue;
                for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}})
                    todo.push_back({c.first + dx, c.second + dy});
            }
            EXPECT_EQ(reached.size(), cells.size()) << "shard " << i << "/" << n << " is not one connected tile";
        }
}

TEST(DatabaseShard, MergeNamesEveryMissingShardAndItsFile)
{
    const std::string dir = freshDir("missing");
    const std::string output = dir + "/db.qdb";
    for (int i : {0, 2}) headerShard({i, 4}, 40, "o").save(reloc::shardPath(output, {i, 4}));
    const std::string e = inputError([&] { reloc::loadShardsForMerge(output, expectation(4, "o")); });
    EXPECT_NE(e.find("db.qdb (merge of 4 shards): shards 1, 3 missing"), std::string::npos) << e;
    EXPECT_NE(e.find("db.qdb.shard-1-of-4"), std::string::npos) << e;
    EXPECT_NE(e.find("db.qdb.shard-3-of-4"), std::string::npos) << e;
    EXPECT_NE(e.find("--shard i/4"), std::string::npos) << e;
    // A whole failed array job: every index, the first files.
    const std::string all = inputError([&] { reloc::loadShardsForMerge(dir + "/none.qdb", expectation(12, "o")); });
    EXPECT_NE(all.find("shards 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11 missing"), std::string::npos) << all;
    EXPECT_NE(all.find("none.qdb.shard-7-of-12' and 4 more not found"), std::string::npos) << all;
    fs::remove_all(dir);
}

TEST(DatabaseShard, MergeNamesAShardOfAnotherMap)
{
    const std::string dir = freshDir("other_map");
    const std::string output = dir + "/db.qdb";
    for (int i = 0; i < 3; ++i)
    {
        reloc::DatabaseShard s = headerShard({i, 3}, 30, "o");
        if (i == 1)
        {
            s.map.file_hash ^= 1;
            s.map_file = "other.map";
        }
        s.save(reloc::shardPath(output, {i, 3}));
    }
    const std::string e = inputError([&] { reloc::loadShardsForMerge(output, expectation(3, "o")); });
    EXPECT_NE(e.find("shard 1/3"), std::string::npos) << e;
    EXPECT_NE(e.find("db.qdb.shard-1-of-3"), std::string::npos) << e;
    EXPECT_NE(e.find("another map"), std::string::npos) << e;
    EXPECT_NE(e.find("other.map"), std::string::npos) << e;
    fs::remove_all(dir);
}

TEST(DatabaseShard, MergeNamesTheOptionAShardWasBuiltWithOtherwise)
{
    const core::CameraModel camera = testCamera();
    const reloc::DatabaseBuildConfig config = smallConfig();
    reloc::DatabaseBuildConfig other = config;
    other.sampling.grid_spacing_m = 0.75;
    const std::string options = reloc::resultOptionsText(config, camera);
    EXPECT_EQ(options.find("//"), std::string::npos) << "values only, no documentation: " << options;
    EXPECT_NE(options.find("[ViewSampling] grid_spacing_m = 1.5\n"), std::string::npos) << options;

    const std::string dir = freshDir("other_options");
    const std::string output = dir + "/db.qdb";
    headerShard({0, 2}, 20, options).save(reloc::shardPath(output, {0, 2}));
    headerShard({1, 2}, 20, reloc::resultOptionsText(other, camera)).save(reloc::shardPath(output, {1, 2}));
    const std::string e = inputError([&] { reloc::loadShardsForMerge(output, expectation(2, options)); });
    EXPECT_NE(e.find("shard 1/2"), std::string::npos) << e;
    EXPECT_NE(e.find("other options"), std::string::npos) << e;
    EXPECT_NE(e.find("[ViewSampling] grid_spacing_m = 0.75 in the shard, 1.5 in the merge's configuration (build.ini)"),
              std::string::npos)
        << e;
    fs::remove_all(dir);
}

TEST(DatabaseShard, OptionsThatDoNotChangeTheResultAreNotCompared)
{
    const core::CameraModel camera = testCamera();
    reloc::DatabaseBuildConfig a = smallConfig(), b = smallConfig();
    b.build.threads = 7;
    b.quasi.num_threads = 3;
    EXPECT_EQ(reloc::resultOptionsText(a, camera), reloc::resultOptionsText(b, camera));
    const std::string options_a = reloc::resultOptionsText(a, camera);
    b.vocabulary.seed = 2;  // the merge trains the vocabulary: its options count
    const std::string seed = reloc::optionsDifference(reloc::resultOptionsText(b, camera), "b", options_a, "a");
    EXPECT_EQ(seed, "[Vocabulary] seed = 2 in b, 1 in a");
    core::CameraModel other_camera = camera;
    other_camera.fx += 1;
    const std::string fx = reloc::optionsDifference(reloc::resultOptionsText(a, other_camera), "b", options_a, "a");
    EXPECT_EQ(fx.rfind("[camera] fx = ", 0), 0u) << fx;
}

TEST(DatabaseShard, MergeNamesACopiedShardFileAndADifferentShardCount)
{
    const std::string dir = freshDir("copied");
    const std::string output = dir + "/db.qdb";
    headerShard({0, 3}, 30, "o").save(reloc::shardPath(output, {0, 3}));
    headerShard({1, 3}, 30, "o").save(reloc::shardPath(output, {1, 3}));
    fs::copy_file(reloc::shardPath(output, {1, 3}), reloc::shardPath(output, {2, 3}));
    std::string e = inputError([&] { reloc::loadShardsForMerge(output, expectation(3, "o")); });
    EXPECT_NE(e.find("db.qdb.shard-2-of-3: holds shard 1/3, not shard 2/3"), std::string::npos) << e;

    // A shard of a 2-shard build renamed into a 3-shard build.
    headerShard({1, 2}, 30, "o").save(reloc::shardPath(output, {2, 3}));
    e = inputError([&] { reloc::loadShardsForMerge(output, expectation(3, "o")); });
    EXPECT_NE(e.find("holds shard 1/2, not shard 2/3"), std::string::npos) << e;
    fs::remove_all(dir);
}

TEST(DatabaseShard, ShardFilesThatAreNotShardsAreNamed)
{
    const std::string dir = freshDir("foreign");
    const std::string path = dir + "/x.shard-0-of-1";
    EXPECT_NE(inputError([&] { reloc::DatabaseShard::load(path); }).find("not found"), std::string::npos);
    {
        std::ofstream(path) << "hello";
    }
    const std::string foreign = inputError([&] { reloc::DatabaseShard::load(path); });
    EXPECT_NE(foreign.find("x.shard-0-of-1: is not a quasiloc database shard"), std::string::npos) << foreign;
    // A truncated shard (a copy cut short) is named, not read.
    headerShard({0, 1}, 10, "o").save(path);
    const std::string bytes = fileBytes(path);
    {
        std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes.substr(0, bytes.size() / 2);
    }
    EXPECT_NE(inputError([&] { reloc::DatabaseShard::load(path); }).find("x.shard-0-of-1"), std::string::npos);
    fs::remove_all(dir);
}

TEST(ShardSelection, ParsesIOfNAndRejectsTheRest)
{
    const auto s = reloc::ShardSelection::parse("3/8", "--shard");
    EXPECT_EQ(s.index, 3);
    EXPECT_EQ(s.count, 8);
    EXPECT_EQ(s.text(), "3/8");
    for (const char* bad : {"8/8", "-1/4", "1/0", "1", "1/2/3", "a/4", "1/4x", "", "/4", "1/", " 1/4", "1/99999999999"})
        EXPECT_NE(inputError([&] { reloc::ShardSelection::parse(bad, "--shard"); }).find("--shard"), std::string::npos)
            << bad;
}

TEST(MapIdentity, TellsFilesApartByTheirBytes)
{
    const std::string dir = freshDir("identity");
    {
        std::ofstream(dir + "/a") << "the same map";
        std::ofstream(dir + "/b") << "the same map";
        std::ofstream(dir + "/c") << "the same maq";
    }
    const auto a = reloc::MapIdentity::ofFile(dir + "/a");
    EXPECT_EQ(a.file_bytes, 12u);
    EXPECT_TRUE(a == reloc::MapIdentity::ofFile(dir + "/b"));
    EXPECT_FALSE(a == reloc::MapIdentity::ofFile(dir + "/c"));
    EXPECT_NE(inputError([&] { reloc::MapIdentity::ofFile(dir + "/missing"); }).find("missing"), std::string::npos);
    fs::remove_all(dir);
}
