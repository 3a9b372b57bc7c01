#pragma once
// A floor of an office building for the ground robot: a long corridor along x with rooms on both sides, built from
// the world builder's primitives (world.h quads and boxes, the procedural materials).
//
// Layout (world frame, z up, floor at z = 0): the corridor spans x in [0, corridor_length_m] and |y| <=
// corridor_width_m / 2; on each side, rooms of depth room_depth_m partition the corridor's length (widths drawn
// around room_width_m), each with one door into the corridor. The building is closed (outer and end walls), so
// every free position lies inside a room or the corridor, and the LiDAR's stations (lidar_sampler.h) land there.
//
// Decisions:
// - The corridor is the weak structure: plain plaster walls, a concrete floor, only corridor_posters posters on its
//   walls; the rooms carry the clutter (tables, shelves, boxes, posters) and walls of mixed materials.
// - Clutter is placed after the robot's path is known: every piece keeps clearance_m from the given positions
//   (the path, at camera height), as the EuRoC rooms keep clear of the flights.
// - Lights: two per room, one every 4 m along the corridor.
#include <Eigen/Geometry>
#include <cstdint>
#include <quasiloc/sim/world.h>
#include <vector>

namespace quasiloc::sim
{
struct WorldOptions;
struct WorldStats;

/** The floor's size and clutter (keys floor_* of [World], sim_options.cpp). */
struct FloorOptions
{
    double corridor_length_m = 24;
    double corridor_width_m = 2.0;
    double room_depth_m = 5.0;
    double room_width_m = 6.0;  ///< mean; each room's width is drawn in [0.75, 1.25] x this
    double ceiling_m = 2.8;
    double door_width_m = 1.4;
    int furniture_per_room = 4;
    int posters_per_room = 3;
    int corridor_posters = 2;
};

struct FloorRoom
{
    Eigen::AlignedBox2d box;  ///< inner extent, x along the corridor
    double door_x = 0;        ///< centre of the door along x
    int side = 1;             ///< +1: y > 0 (north of the corridor), -1: south
};

struct FloorLayout
{
    double corridor_length = 0, corridor_half_width = 0, ceiling = 0, door_width = 0, door_height = 2.1;
    std::vector<FloorRoom> rooms;
    Eigen::AlignedBox3d extent;  ///< the building's inner extent, floor to ceiling

    /** True when p lies in the corridor or inside a room at least `margin` from its walls (doors not counted). */
    bool isFree(const Eigen::Vector2d& p, double margin) const;
};

/** The layout of `options` for `seed` (room widths and doors drawn from it). InputError naming `input` for a
 *  corridor shorter than one room or a door wider than a room can hold. */
FloorLayout makeFloorLayout(const FloorOptions& options, uint64_t seed, const std::string& input);

/** The world of `layout`: walls, floor, ceiling, lights, clutter clear of `keep_clear` by options.clearance_m;
 *  materials, texture size, cell size, light intensity, ambient and shadows from `options`. */
World buildFloorWorld(const WorldOptions& options, const FloorLayout& layout, uint64_t seed,
                      const std::vector<Eigen::Vector3f>& keep_clear, WorldStats* stats = nullptr);

}  // namespace quasiloc::sim
