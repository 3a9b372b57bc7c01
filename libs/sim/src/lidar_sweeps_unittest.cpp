#include <gtest/gtest.h>

#include <quasiloc/sim/lidar_sweeps.h>
#include <quasiloc/sim/world_builder.h>

using namespace quasiloc;

namespace
{
const std::string kShared = QUASILOC_SHARED_DIR;

const sim::World& testWorld()
{
    static const sim::World w = [] {
        sim::WorldOptions o;
        o.texture_size_px = 256;
        return sim::buildWorld(o, kShared, 3, sim::loadRoomTrajectoryPositions(kShared, "v1"));
    }();
    return w;
}

/** A cheap mapping run: every 12th sweep, half the azimuth resolution, small cube maps. */
sim::LidarOptions cheapSweeps()
{
    sim::LidarOptions o;
    o.map_source = sim::MapSource::sweeps;
    o.sweep_every = 12;
    o.sweep_azimuth_steps = 900;
    o.sweep_cubemap_px = 512;
    o.sweep_voxel_m = 0.04;
    o.sweep_people = 2;
    o.sweep_furniture = 0;
    o.sweep_glass_panes = 2;
    return o;
}

const sim::SweptMap& sweptMap()
{
    static const sim::SweptMap m = sim::buildSweptMap(testWorld(), {}, cheapSweeps(), 7, "test swept map");
    return m;
}
}  // namespace

TEST(LidarSweeps, MapLiesOnTheTrueSurfacesAndCoversThem)
{
    const sim::SweptMap& m = sweptMap();
    const sim::SweptMapQuality& q = m.quality;
    std::cout << m.summary() << std::endl;
    ASSERT_GT(q.points, 50000u);
    // 2.5 cm range noise averaged over the few returns of a 4 cm voxel (a single return's median error is 1.7 cm),
    // 2 cm / 0.2 deg pose error, mixed returns at depth edges, people's points the carving left.
    EXPECT_LT(q.median_error_m, 0.02);
    EXPECT_LT(q.p95_error_m, 0.08);
    EXPECT_LT(q.share_beyond_10cm, 0.04);
    EXPECT_GT(q.coverage, 0.6);
    EXPECT_GT(m.sweeps.mixed, 0u);                     // beam divergence at depth edges
    EXPECT_EQ(m.build.deskewed_scans, m.build.scans);  // per-point times reach map-build
}

TEST(LidarSweeps, WithoutNoiseDivergenceOrDriftTheMapIsExact)
{
    // Checks the geometry of the chain: the exact beam-triangle intersections, the LiDAR frame at each firing's time,
    // map-build's deskewing with the run's poses.
    sim::LidarOptions o = cheapSweeps();
    o.sweep_every = 24;
    o.sweep_drift_m = 0;
    o.sweep_drift_deg = 0;
    o.sweep_range_noise_mm = 0;
    o.sweep_divergence_mrad = 0;
    o.sweep_people = 0;
    const sim::SweptMap m = sim::buildSweptMap(testWorld(), {}, o, 7, "test swept map");
    std::cout << m.summary() << std::endl;
    EXPECT_LT(m.quality.median_error_m, 0.001);
    EXPECT_LT(m.quality.p95_error_m, 0.005);
    EXPECT_LT(m.quality.share_beyond_10cm, 0.002);
    EXPECT_EQ(m.sweeps.mixed, 0u);
}

TEST(LidarSweeps, GlassReturnsNothing)
{
    const sim::SweptMap& m = sweptMap();
    ASSERT_EQ(m.scene.glass.size(), 2u);
    EXPECT_GT(m.sweeps.glass_dropped, 1000u);
    EXPECT_EQ(m.quality.glass_points, 0u);
}

TEST(LidarSweeps, PeopleWalkingWhileMappingAreCarvedOut)
{
    const sim::SweptMap& m = sweptMap();
    ASSERT_EQ(m.scene.people.size(), 2u);
    const sim::SweptMapQuality& q = m.quality;
    ASSERT_GT(q.person_points_fused, 200u);
    EXPECT_GT(double(q.person_points_removed), 0.6 * double(q.person_points_fused));
}

TEST(LidarSweeps, FurnitureStandingWhileMappingStaysInTheMap)
{
    sim::LidarOptions o = cheapSweeps();
    o.sweep_every = 30;
    o.sweep_people = 0;
    o.sweep_furniture = 2;  // the first stays all along, the second moves half-way
    const sim::SweptMap m = sim::buildSweptMap(testWorld(), {}, o, 7, "test swept map");
    ASSERT_EQ(m.scene.furniture.size(), 2u);
    EXPECT_FALSE(m.scene.furniture[0].moved);
    EXPECT_TRUE(m.scene.furniture[1].moved);
    // The camera never sees it, map-build cannot know: points the tracker will find no image evidence for.
    EXPECT_GT(m.quality.furniture_points_fused - m.quality.furniture_points_removed, 100u);
}

TEST(LidarSweeps, DriftStaysWithinItsBoundsAndVanishesAtLoopClosures)
{
    sim::LidarOptions o = cheapSweeps();
    o.sweep_drift_m = 0.03;
    o.sweep_drift_deg = 0.3;
    const sim::MappingRun run = sim::planMappingRun(testWorld(), {}, o, 11);
    ASSERT_GT(run.duration(), 30.0);
    ASSERT_GE(run.loop_closure_t.size(), 1u);
    const auto [drift_m, drift_deg] = sim::mappingRunDrift(run);
    EXPECT_NEAR(drift_m, 0.03, 1e-4);
    EXPECT_NEAR(drift_deg, 0.3, 1e-3);
    auto error_m = [&](double t) { return (run.pose(t).translation() - run.pose(t, true).translation()).norm(); };
    EXPECT_LT(error_m(0), 1e-9);
    for (double t : run.loop_closure_t) EXPECT_LT(error_m(t), 0.003) << "at the closure at " << t << " s";
    // A random walk between closures: half-way it is not near zero everywhere.
    double largest_between = 0;
    for (double t = 0; t < run.duration(); t += 0.5) largest_between = std::max(largest_between, error_m(t));
    EXPECT_GT(largest_between, 0.02);
    // The run stays in the room, at the configured heights.
    for (const Eigen::Isometry3d& T : run.T_world_lidar)
    {
        EXPECT_TRUE(testWorld().room.contains(T.translation().cast<float>()));
        EXPECT_GE(T.translation().z() - testWorld().room.min().z(), o.sweep_min_height_m - 1e-6);
        EXPECT_LE(T.translation().z() - testWorld().room.min().z(), o.sweep_max_height_m + 1e-6);
    }
}

TEST(LidarSweeps, DeterministicForASeed)
{
    sim::LidarOptions o = cheapSweeps();
    o.sweep_every = 100;
    o.sweep_pattern = sim::SweepPattern::rosette;
    o.rosette_points_per_s = 20000;
    const sim::MappingRun run = sim::planMappingRun(testWorld(), {}, o, 3);
    const sim::MappingScene scene = sim::makeMappingScene(testWorld(), run, o, 3);
    const sim::SimulatedSweeps a = sim::simulateSweeps(testWorld(), scene, run, o, 3);
    const sim::SimulatedSweeps b = sim::simulateSweeps(testWorld(), scene, run, o, 3);
    const sim::SimulatedSweeps c = sim::simulateSweeps(testWorld(), scene, run, o, 4);
    ASSERT_GE(a.size(), 3u);
    ASSERT_EQ(a.size(), b.size());
    bool differs = false;
    for (size_t i = 0; i < a.size(); ++i)
    {
        ASSERT_GT(a.scans[i].size(), 1000u);
        ASSERT_EQ(a.scans[i].size(), b.scans[i].size());
        for (size_t k = 0; k < a.scans[i].size(); ++k)
        {
            ASSERT_EQ(a.scans[i].points[k], b.scans[i].points[k]);
            ASSERT_EQ(a.scans[i].intensity[k], b.scans[i].intensity[k]);
        }
        differs |= c.scans[i].size() != a.scans[i].size() || c.scans[i].points[0] != a.scans[i].points[0];
    }
    EXPECT_TRUE(differs);
}

TEST(LidarSweeps, IntensitiesAreEightBitWithPerRingGains)
{
    sim::LidarOptions o = cheapSweeps();
    o.sweep_every = 100;
    o.sweep_people = 0;
    const sim::MappingRun run = sim::planMappingRun(testWorld(), {}, o, 5);
    const sim::MappingScene scene = sim::makeMappingScene(testWorld(), run, o, 5);
    const sim::SimulatedSweeps s = sim::simulateSweeps(testWorld(), scene, run, o, 5);
    ASSERT_GE(s.size(), 1u);
    const map::LidarScan& scan = s.scans[0];
    ASSERT_EQ(scan.ring.size(), scan.size());
    ASSERT_EQ(scan.time_s.size(), scan.size());
    for (size_t k = 0; k < scan.size(); ++k)
    {
        ASSERT_EQ(scan.intensity[k], std::round(scan.intensity[k]));
        ASSERT_GE(scan.intensity[k], 0.f);
        ASSERT_LE(scan.intensity[k], 255.f);
        ASSERT_LT(scan.ring[k], o.sweep_beams);
        ASSERT_GE(scan.time_s[k], 0.0);
        ASSERT_LT(scan.time_s[k], 0.1);
    }
}
