// The large test world (large_world.h): the base room at the centre, other simulated rooms on a grid around it.
#include <quasiloc/core/error.h>
#include <quasiloc/core/ini_read.h>
#include <quasiloc/sim/large_world.h>

#include <chrono>
#include <cmath>
#include <random>

namespace quasiloc::sim
{
void LargeWorldOptions::declare(core::OptionTable& t)
{
    using core::Range;
    t.add("base_map", base_map, "the room the camera flies in: placed unchanged at the centre cell");
    t.add("output", output, "the world's LiDAR map file");
    t.add("shared_dir", shared_dir, "the EuRoC room data the other rooms are built from");
    t.add("grid_cells", grid_cells, "", Range::between(1, 101), "cells per side of the square grid (odd)");
    t.add("spacing_m", spacing_m, "m", Range::atLeast(20), "distance between neighbouring cell centres");
    t.add("seed", seed, "", Range::atLeast(0), "the other rooms: room k uses seed + k (clutter, yaw, LiDAR noise)");
}

void LargeWorldOptions::check(const std::string& input) const
{
    checkRanges(input, "LargeWorld");
    core::require(grid_cells % 2 == 1, input + ": " + core::iniKeyName("LargeWorld", "grid_cells"),
                  "must be odd (the base map takes the centre cell)");
}

namespace
{
/** Appends `room` turned by yaw about the vertical through its horizontal centre, then moved to `centre`. */
void appendRoom(map::LidarMap& out, const map::LidarMap& room, double yaw, const Eigen::Vector2d& centre)
{
    const map::MapBounds b = room.bounds();
    const float cx = 0.5f * (b.min.x() + b.max.x()), cy = 0.5f * (b.min.y() + b.max.y());
    const float c = float(std::cos(yaw)), s = float(std::sin(yaw));
    for (size_t i = 0; i < room.size(); ++i)
    {
        const float x = room.xs()[i] - cx, y = room.ys()[i] - cy;
        out.addPoint(float(centre.x()) + c * x - s * y, float(centre.y()) + s * x + c * y, room.zs()[i],
                     room.reflectivity(i));
    }
}
}  // namespace

map::LidarMap buildLargeWorld(const map::LidarMap& base, const LargeWorldOptions& o, const WorldOptions& world,
                              const LidarOptions& lidar, const std::string& input, LargeWorldStats* stats,
                              const LargeWorldProgress& progress)
{
    o.check(input);
    if (stats) *stats = {};
    world.check(input);
    lidar.check(input);
    core::require(lidar.map_source == MapSource::exact, input + ": " + core::iniKeyName("Lidar", "map_source"),
                  "must be exact: the other rooms are sampled by the exact sampler (a swept map per room would take "
                  "minutes each)");
    base.check(o.base_map.empty() ? "the base map" : o.base_map);
    const auto t0 = std::chrono::steady_clock::now();
    const int half = o.grid_cells / 2, total = o.grid_cells * o.grid_cells - 1;
    const map::MapBounds bb = base.bounds();
    const Eigen::Vector2d base_centre(0.5 * (bb.min.x() + bb.max.x()), 0.5 * (bb.min.y() + bb.max.y()));

    map::LidarMap out;
    out.reserve(base.size() * size_t(total + 1));
    for (size_t i = 0; i < base.size(); ++i)
        out.addPoint(base.xs()[i], base.ys()[i], base.zs()[i], base.reflectivity(i));

    const std::vector<Eigen::Vector3f> keep_clear[2] = {loadRoomTrajectoryPositions(o.shared_dir, "v1"),
                                                        loadRoomTrajectoryPositions(o.shared_dir, "v2")};
    int done = 0;
    for (int gy = -half; gy <= half; ++gy)
        for (int gx = -half; gx <= half; ++gx)
        {
            if (gx == 0 && gy == 0) continue;
            const uint64_t seed = uint64_t(o.seed) + uint64_t(done);
            WorldOptions w = world;
            w.world = (done % 2 == 0) ? ViconRoom::v2 : ViconRoom::v1;  // neighbours differ
            const World room = buildWorld(w, o.shared_dir, seed, keep_clear[w.world == ViconRoom::v1 ? 0 : 1]);
            const map::LidarMap room_map = sampleSurveyMap(room, lidar, seed);
            std::mt19937_64 rng(seed);
            const double yaw = std::uniform_real_distribution<double>(0, 2 * M_PI)(rng);
            appendRoom(out, room_map, yaw, base_centre + o.spacing_m * Eigen::Vector2d(gx, gy));
            if (stats) stats->room_points.push_back(room_map.size());
            ++done;
            if (progress) progress(done, total);
        }

    if (stats)
    {
        const map::MapBounds b = out.bounds();
        stats->rooms = size_t(total);
        stats->base_points = base.size();
        stats->area_km2 = double(b.max.x() - b.min.x()) * double(b.max.y() - b.min.y()) * 1e-6;
        stats->generation_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    return out;
}

}  // namespace quasiloc::sim
