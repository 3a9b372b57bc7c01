#include <gtest/gtest.h>

#include <quasiloc/core/error.h>
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/sim/world_builder.h>

using namespace quasiloc;

namespace
{
const std::string kShared = QUASILOC_SHARED_DIR;
}

TEST(WorldBuilder, AllSixTrajectoriesKeepClearanceFromGeometry)
{
    for (const std::string world : {"v1", "v2"})
    {
        sim::WorldOptions o;
        o.world = world;
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
    for (size_t i = 0; !differs && i < a.mesh.vertices.size(); ++i) differs = a.mesh.vertices[i].p != c.mesh.vertices[i].p;
    EXPECT_TRUE(differs);
}

TEST(WorldBuilder, RejectsBadOptions)
{
    sim::WorldOptions o;
    o.world = "v3";
    EXPECT_THROW(sim::buildWorld(o, kShared, 1, {}), core::InputError);
    o.world = "v1";
    EXPECT_THROW(sim::buildWorld(o, "/nonexistent", 1, {}), core::InputError);
}
