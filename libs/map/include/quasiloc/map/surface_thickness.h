#pragma once
// The thickness of a map's surfaces: how far its points scatter across the surface they lie on, measured from the
// map alone. A map sampled from exact surfaces (a survey scanner, the simulator's exact sampler) is a few
// millimetres thick; a map fused from a mobile LiDAR's sweeps is one to three centimetres thick (range noise
// wider than a voxel spreads a wall over several voxel layers, and the mapping run's pose drift doubles surfaces).
// The tracker decides from it whether the map's reflectivity edges, rendered from those points, are exact enough
// for the edge term (tracking_options.h, map_term = auto).
//
// Measured as the median, over patches of radius radius_m around sample points, of the square root of the
// smallest eigenvalue of the patch's covariance, counting only patches spread in two directions (a surface, not an
// edge or a pole). The median leaves out corners and clutter, which are a minority of the patches of any map.
#include <cstddef>
#include <string>
#include <quasiloc/map/lidar_map.h>

namespace quasiloc::map
{
struct SurfaceThicknessOptions
{
    double radius_m = 0.12;  ///< patch radius: wide enough for a dozen points of a 5 cm voxel map
    int samples = 4000;      ///< sample points (deterministic pseudo-random choice)
    int min_points = 10;     ///< a patch with fewer points is skipped
    /** A patch is a surface when its second eigenvalue is at least this share of its largest. */
    double min_spread_ratio = 0.25;
};

struct SurfaceThickness
{
    double median_m = 0;         ///< the map's surface thickness (0 when no patch was a surface)
    double p90_m = 0;            ///< the 90th percentile over the surface patches
    size_t surface_patches = 0;  ///< patches that counted
    size_t sampled_patches = 0;  ///< patches looked at
};

/** One pass over the map's points plus one patch per sample: about 0.1 s for 2 M points. */
SurfaceThickness measureSurfaceThickness(const LidarMap& map, const SurfaceThicknessOptions& options = {});
/** "median 2.1 mm, p90 4.0 mm (3512 of 4000 patches are surfaces)": what map-import, map-build and quasiloc-track
 *  print, so a user can see how exact a map is. */
std::string describe(const SurfaceThickness& t);

}  // namespace quasiloc::map
