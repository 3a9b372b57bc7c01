#include <gtest/gtest.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/sim/world_builder.h>

using namespace quasiloc;

namespace
{
const std::string kShared = QUASILOC_SHARED_DIR;
}

TEST(WorldBuilder, AllSixTrajectoriesKeepClearanceFromGeometry)
{
    for (const sim::ViconRoom room : {sim::ViconRoom::v1, sim::ViconRoom::v2})
    {
        const std::string world = sim::roomName(room);
        sim::WorldOptions o;
        o.world = room;
        const auto keep_clear = sim::loadRoomTrajectoryPositions(kShared, world);
        sim::WorldStats st;
        const sim::World w = sim::buildWorld(o, kShared, 1, keep_clear, &st);
        EXPECT_GT(st.gmm_patches, 500u) << world;
        EXPECT_GT(st.objects_placed, 10u) << world;
        // Independent check, sequence by sequence, of every ground-truth sample against every triangle.
        for (const std::string& seq : sim::roomSequences(world))
        {
            const auto traj = core::readTum(kShared + "/data/euroc/groundtruth/cam0/" + seq + ".txt");
            std::vector<Eigen::Vector3f> pos;
            for (const auto& p : traj.poses) pos.emplace_back(p.pose.x(), p.pose.y(), p.pose.z());
            const double clearance = sim::minClearance(w.mesh, pos);
            EXPECT_GE(clearance, o.clearance_m - 1e-4) << seq;
            std::cout << seq << " min clearance " << clearance << " m\n";
        }
        // Every camera position is inside the room shell.
        for (const auto& p : keep_clear) EXPECT_TRUE(w.room.contains(p)) << world;
    }
}

TEST(WorldBuilder, DeterministicForASeed)
{
    sim::WorldOptions o;
    o.gmm_patches = false;  // objects and shell only: fast
    const sim::World a = sim::buildWorld(o, kShared, 7, {});
    const sim::World b = sim::buildWorld(o, kShared, 7, {});
    const sim::World c = sim::buildWorld(o, kShared, 8, {});
    ASSERT_EQ(a.mesh.vertices.size(), b.mesh.vertices.size());
    for (size_t i = 0; i < a.mesh.vertices.size(); ++i) ASSERT_EQ(a.mesh.vertices[i].p, b.mesh.vertices[i].p);
    EXPECT_EQ(cv::norm(a.materials[0].albedo_mips[0], b.materials[0].albedo_mips[0], cv::NORM_INF), 0.0);
    bool differs = a.mesh.vertices.size() != c.mesh.vertices.size();
    for (size_t i = 0; !differs && i < a.mesh.vertices.size(); ++i)
        differs = a.mesh.vertices[i].p != c.mesh.vertices[i].p;
    EXPECT_TRUE(differs);
}

TEST(WorldBuilder, RejectsBadOptions)
{
    sim::WorldOptions o;
    mrpt::config::CConfigFileMemory cfg;
    cfg.setContent("[World]\nworld = v3\n");
    EXPECT_THROW(core::loadOptionsChecked(o, cfg, "World", "test.ini"), core::InputError);
    o.texture_size_px = 100;  // in range, not a power of two
    EXPECT_THROW(sim::buildWorld(o, kShared, 1, {}), core::InputError);
    o.texture_size_px = 128;
    o.num_lights = 0;  // set in code: the declared range still holds
    EXPECT_THROW(sim::buildWorld(o, kShared, 1, {}), core::InputError);
    o.num_lights = 6;
    EXPECT_THROW(sim::buildWorld(o, "/nonexistent", 1, {}), core::InputError);
}
