#pragma once
// A large test world (docs/large_maps.md): the simulated room the camera flies in, unchanged at the centre of a square
// grid of cells, and in every other cell another simulated room (v1 or v2, each with its own procedural clutter from
// its own seed) turned by a random yaw: a campus of rooms that are alike but not copies, so a search over the whole
// world is a real search. The cells are spacing_m apart; there is nothing between them (no ground: a 4 cm distance
// field over a square kilometre of ground would hold some 40 GB of bricks).
//
// Options: [LargeWorld] (LargeWorldOptions::declare, large_world.cpp); the rooms use [World] and [Lidar].
#include <functional>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/sim/lidar_sampler.h>
#include <quasiloc/sim/world_builder.h>
#include <string>
#include <vector>

namespace quasiloc::sim
{
struct LargeWorldOptions : public core::DeclaredOptions
{
    std::string base_map;  ///< the room the camera flies in (its own frame is the world frame)
    std::string output = "out/large_world/world.map";
    std::string shared_dir = "../shared";
    int grid_cells = 7;      ///< cells per side (odd: the base map takes the centre)
    double spacing_m = 170;  ///< between cell centres
    int seed = 100;

    void declare(core::OptionTable& t) override;
    /** The declared ranges, then grid_cells odd (InputError naming `input` and the key). */
    void check(const std::string& input) const;
};

struct LargeWorldStats
{
    size_t rooms = 0;                 ///< rooms added around the base map
    size_t base_points = 0;           ///< the base map's points (the world's first points, in its order)
    std::vector<size_t> room_points;  ///< the other rooms' points, in the order they follow the base map
    double area_km2 = 0;              ///< of the world's horizontal bounding box
    double generation_s = 0;
};

/** Progress: (rooms done, rooms in total). */
using LargeWorldProgress = std::function<void(int done, int total)>;

/** The world: base's points first (unchanged, in order), then the other cells' rooms row by row. InputError naming
 *  `input` for bad options. */
map::LidarMap buildLargeWorld(const map::LidarMap& base, const LargeWorldOptions& options, const WorldOptions& world,
                              const LidarOptions& lidar, const std::string& input, LargeWorldStats* stats = nullptr,
                              const LargeWorldProgress& progress = {});

}  // namespace quasiloc::sim
