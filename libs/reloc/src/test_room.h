#pragma once
// Shared by the reloc tests: the simulated Vicon room v1 (textures kept small) and its LiDAR survey at the main
// job's density.
#include <quasiloc/sim/lidar_sampler.h>
#include <quasiloc/sim/world_builder.h>
#include <string>

namespace quasiloc::reloc::test
{
inline sim::World testRoom(const std::string& shared_dir)
{
    sim::WorldOptions wo;
    wo.texture_size_px = 256;
    return sim::buildWorld(wo, shared_dir, 3, sim::loadRoomTrajectoryPositions(shared_dir, "v1"));
}

inline map::LidarMap testRoomMap(const sim::World& world)
{
    sim::LidarOptions lo;
    lo.density_per_m2 = 6000;  // the main job's density: sparser maps give quasi-images with more holes
    lo.cubemap_size_px = 512;
    return sim::sampleSurveyMap(world, lo, 5);
}
}  // namespace quasiloc::reloc::test
