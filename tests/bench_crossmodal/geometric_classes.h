#pragma once
// Surface classes of a street-scene LiDAR map that has no labels, from geometry and reflectivity alone:
//  1. ground: per ground_cell_m cell the 5th percentile of z, cells standing more than ground_max_step_m above the
//     median of the 5 x 5 cells around them (cells holding only a vehicle or a wall) lowered to it; a point within
//     ground_band_m of the interpolated ground height is ground;
//  2. road: ground whose local normal is up (|n_z| >= road_min_up) and whose neighbourhood is flat (plane residual
//     below road_max_rough_m); other ground (verges, gravel, grass) is "other";
//  3. marking: a road point brighter than the road around it (its ground cell's median) by marking_delta and at
//     least marking_min in absolute reflectivity;
//  4. the road region: the 2D cells (region_cell_m) holding road or marking points, closed and grown by
//     vehicle_reach_m (a vehicle hides the road under it and a lane beside it); every point above the ground and at
//     most vehicle_max_height_m high in it is a vehicle (a map fused from scans of a slowly moving queue smears its
//     vehicles into volumes that connect with everything around them: no cluster of a vehicle stands alone);
//  5. the other points above the ground: vegetation where the neighbourhood is scattered (smallest / largest
//     eigenvalue of its covariance >= vegetation_min_scatter), facade where it is planar (planarity >=
//     facade_min_planarity) with a horizontal normal (|n_z| <= facade_max_up) in a column (region_cell_m) reaching
//     facade_min_height_m above the ground, else other.
// Up is +z of the map frame (KITTI: the velodyne frame of the first scan).
#include <array>
#include <cstdint>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/sim/surface_class.h>
#include <vector>

namespace quasiloc::bench
{
/** Section [GeometricClasses] of bench_crossmodal_stats. */
struct GeometricClassOptions : public core::DeclaredOptions
{
    double ground_cell_m = 2.0;
    double ground_band_m = 0.15;
    double ground_max_step_m = 1.0;
    double feature_radius_m = 0.3;
    double road_min_up = 0.85;
    double road_max_rough_m = 0.06;
    double marking_delta = 0.15;
    double marking_min = 0.35;
    double region_cell_m = 0.5;
    double vehicle_reach_m = 2.0;
    double vehicle_max_height_m = 4.5;
    double vegetation_min_scatter = 0.12;
    double facade_min_planarity = 0.5;
    double facade_max_up = 0.3;
    double facade_min_height_m = 2.0;

    void declare(core::OptionTable& t) override;
};

struct GeometricClassStats
{
    std::array<size_t, sim::kNumSurfaceClasses> points{};
    double road_region_m2 = 0;  ///< area of the road region (step 4)
    double seconds = 0;
};

/** One class per map point (sim::SurfaceClass as uint8_t), in map order. */
std::vector<uint8_t> classifyGeometrically(const map::LidarMap& map, const GeometricClassOptions& options,
                                           GeometricClassStats* stats = nullptr);

}  // namespace quasiloc::bench
