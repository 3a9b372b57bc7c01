#pragma once
// An outdoor world: a campus of square blocks on a street grid, built from the world builder's primitives (world.h
// quads, boxes and cylinders) and the outdoor materials (asphalt, road paint, glass, foliage, bark, car paint).
//
// Layout (world frame, z up, road surface at z = 0): street centrelines run along x and y at k x block_size_m,
// k = 0..blocks_per_side, so the streets enclose blocks_per_side^2 blocks and the campus spans
// (blocks_per_side x block_size_m)^2 between its outer streets (10 blocks of 100 m: 1 km^2). Beyond the outer streets a
// margin of pavement ends at a low boundary wall.
//  - ground: continuous; asphalt carriageways street_width_m wide (kerb to kerb), intersections included; each block a
//    raised slab (kerb 0.15 m) whose outer sidewalk_width_m is the sidewalk;
//  - road markings (kRoadPaint, 5 mm above the asphalt): a dashed centre line on every street and zebra crossings
//    on every approach to an intersection; the paint is bright at 905 nm, so the markings show in the reflectivity;
//  - buildings: one to three per block, heights drawn in [building_min_height_m, building_max_height_m], facades of
//    plaster, concrete or wood with rows of windows (kGlass panes 3 cm off the facade: the camera sees a dark pane,
//    the LiDAR gets no return, lidar_sweeps.h);
//  - trees (trunk + crown) and standing people on the sidewalks, cars parked along the kerbs (body + glass cabin);
//    everything except the ground keeps clearance_m from the given positions (the route at camera height);
//  - light: a sun (one point light far above) and a bright ambient (the sky).
// Nothing moves: the people stand, the cars are parked.
//
// Decisions: triangles as large as [World] max_cell_m allows (the ground and facades are flat; the campus ini sets
// 2 m, so a 1 km^2 campus stays near a million triangles for the renderer and the LiDAR's cube maps).
#include <Eigen/Geometry>
#include <cstdint>
#include <quasiloc/sim/world.h>
#include <string>
#include <vector>

namespace quasiloc::sim
{
struct WorldOptions;
struct WorldStats;

/** The campus's size and furniture (keys campus_* of [World], sim_options.cpp). */
struct CampusOptions
{
    double block_size_m = 60;  ///< street centreline spacing
    int blocks_per_side = 2;
    double street_width_m = 12;  ///< kerb to kerb: two driving lanes and a parking strip on each side
    double sidewalk_width_m = 3;
    double building_min_height_m = 8;
    double building_max_height_m = 24;
    double storey_m = 3.2;  ///< one row of windows per storey
    int trees_per_side = 4;
    int parked_cars_per_side = 3;
    int people_per_side = 2;
    double margin_m = 12;  ///< pavement beyond the outer streets, up to the boundary wall
};

struct CampusLayout
{
    int blocks = 0;
    double pitch = 0, street_half = 0, sidewalk = 0, kerb = 0.15;
    Eigen::AlignedBox2d extent;  ///< the ground, up to the boundary wall

    /** Street centreline k (along x or along y): k x pitch. */
    double street(int k) const { return k * pitch; }
    /** Block (i, j): the raised slab, sidewalks included. */
    Eigen::AlignedBox2d block(int i, int j) const;
    /** True on a carriageway (streets and intersections) at least `margin` from a kerb. */
    bool onCarriageway(const Eigen::Vector2d& p, double margin) const;
};

/** The layout of `options`. InputError naming `input` for blocks too small for their streets and sidewalks. */
CampusLayout makeCampusLayout(const CampusOptions& options, const std::string& input);

/** The world of `layout` for `seed`; furniture clear of `keep_clear` by options.clearance_m; materials, texture size,
 *  cell size, ambient and shadows from `options` (light_intensity scales the sun). */
World buildCampusWorld(const WorldOptions& options, const CampusLayout& layout, uint64_t seed,
                       const std::vector<Eigen::Vector3f>& keep_clear, WorldStats* stats = nullptr);

/** A mapping tour of every street: along each street along x in turn (serpentine), then each along y, on the
 *  centrelines (z = 0: the mapping run sets its height). */
std::vector<Eigen::Vector3f> campusMappingTour(const CampusLayout& layout);

}  // namespace quasiloc::sim
