#include <gtest/gtest.h>

#include <quasiloc/core/error.h>
#include <quasiloc/sim/large_world.h>

#include <random>
#include <set>

using namespace quasiloc;

namespace
{
const std::string kShared = QUASILOC_SHARED_DIR;

map::LidarMap smallBase()
{
    map::LidarMap m;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> U(0.f, 1.f);
    for (int i = 0; i < 5000; ++i) m.addPoint(-4 + 8 * U(rng), -3 + 6 * U(rng), 3 * U(rng), U(rng));
    return m;
}

/** A quick world: 3 x 3 cells, sparse LiDAR from one station. */
map::LidarMap quickWorld(const map::LidarMap& base, sim::LargeWorldStats* st)
{
    sim::LargeWorldOptions o;
    o.shared_dir = kShared;
    o.grid_cells = 3;
    o.spacing_m = 40;
    sim::LidarOptions lidar;
    lidar.map_source = sim::MapSource::exact;
    lidar.density_per_m2 = 30;
    lidar.num_stations = 1;
    lidar.cubemap_size_px = 128;
    sim::WorldOptions world;
    world.texture_size_px = 64;  // the camera's textures: not used by the LiDAR
    world.shadow_map_px = 64;
    return sim::buildLargeWorld(base, o, world, lidar, "test", st);
}
}  // namespace

TEST(LargeWorld, TheBaseMapComesFirstUnchangedAndDifferentRoomsSurroundIt)
{
    const map::LidarMap base = smallBase();
    sim::LargeWorldStats st;
    const map::LidarMap world = quickWorld(base, &st);
    ASSERT_EQ(st.rooms, 8u);
    ASSERT_EQ(st.room_points.size(), 8u);
    size_t total = base.size();
    for (size_t n : st.room_points) total += n;
    EXPECT_EQ(world.size(), total);
    for (size_t i = 0; i < base.size(); ++i)
    {
        ASSERT_EQ(world.point(i), base.point(i)) << i;
        ASSERT_EQ(world.reflectivity(i), base.reflectivity(i)) << i;
    }
    // Rooms of their own (seed, clutter, v1/v2): not all the same number of points.
    EXPECT_GT(std::set<size_t>(st.room_points.begin(), st.room_points.end()).size(), 1u);
    // The grid spans two spacings plus a room in x and y.
    const map::MapBounds b = world.bounds();
    EXPECT_GT(b.max.x() - b.min.x(), 80.f);
    EXPECT_GT(b.max.y() - b.min.y(), 80.f);
    EXPECT_NEAR(st.area_km2, double(b.max.x() - b.min.x()) * (b.max.y() - b.min.y()) * 1e-6, 1e-6);
    // Deterministic.
    sim::LargeWorldStats again;
    const map::LidarMap world2 = quickWorld(base, &again);
    ASSERT_EQ(world2.size(), world.size());
    EXPECT_EQ(world2.point(world.size() - 1), world.point(world.size() - 1));
}

TEST(LargeWorld, ASweptMapIsAnErrorNamingTheKey)
{
    sim::LargeWorldOptions o;
    o.shared_dir = kShared;
    sim::LidarOptions lidar;
    lidar.map_source = sim::MapSource::sweeps;
    try
    {
        sim::buildLargeWorld(smallBase(), o, sim::WorldOptions{}, lidar, "world.ini");
        FAIL() << "no error";
    }
    catch (const core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("world.ini: [Lidar] map_source"), std::string::npos) << e.what();
    }
}

TEST(LargeWorld, AnEvenGridIsAnErrorNamingTheKey)
{
    sim::LargeWorldOptions o;
    o.grid_cells = 4;
    try
    {
        sim::buildLargeWorld(smallBase(), o, sim::WorldOptions{}, sim::LidarOptions{}, "world.ini");
        FAIL() << "no error";
    }
    catch (const core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("world.ini: [LargeWorld] grid_cells"), std::string::npos) << e.what();
    }
}
