#pragma once
// Synthetic LiDAR maps with known geometry and reflectivity, for tests and benchmarks of the renderer
// (and of anything that consumes quasi-images): planar patches sampled on a jittered grid.
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <quasiloc/map/lidar_map.h>

namespace quasiloc::quasi
{
/** Reflectivity in [0, 1] as a function of the position (s, t), in metres along a patch's two axes. */
using ReflectivityPattern = std::function<float(float s_m, float t_m)>;

/** A checkerboard of `cell_m` squares (0.25 / 0.75) modulated by slow stripes: strong, well-localised
 *  contrast for features, as painted or textured walls give. */
ReflectivityPattern checkerPattern(float cell_m);
/** A constant reflectivity. */
ReflectivityPattern constantPattern(float reflectivity);

/** Appends the parallelogram origin + s * axis_u + t * axis_v (s, t in [0, 1]) sampled every spacing_m along
 *  both axes, each sample jittered by up to jitter * spacing_m (deterministic for a given seed).
 *  Returns the number of points added. */
size_t addPlanarPatch(map::LidarMap& map, const Eigen::Vector3f& origin, const Eigen::Vector3f& axis_u,
                      const Eigen::Vector3f& axis_v, float spacing_m, const ReflectivityPattern& reflectivity,
                      float jitter = 0.3f, uint32_t seed = 1);

/** A closed box room [-size/2, size/2] x [-size/2, size/2] x [0, height] (floor, ceiling, four walls) with
 *  a few boxes standing in it, all with checker patterns, sampled so that the map has about
 *  `approx_points` points. */
map::LidarMap makeSyntheticRoom(size_t approx_points, float size_m = 8.0f, float height_m = 3.0f);

}  // namespace quasiloc::quasi
