#pragma once
// A .3Dscene of a tracking run for SceneViewer3D: the LiDAR map (gray by reflectivity, subsampled), the ground
// truth (green) and the estimate (red) as polylines of the left camera's positions, and the estimate's camera
// frames every `axes_every` poses.
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/map/lidar_map.h>
#include <string>

namespace quasiloc::app
{
/** Writes the scene to `path` (MRPT's COpenGLScene serialization; open with SceneViewer3D). max_map_points: the
 *  map is subsampled evenly to at most this many points. InputError when the file cannot be written. */
void writeTrackingScene(const std::string& path, const map::LidarMap& map, const core::Trajectory& groundtruth,
                        const core::Trajectory& estimate, size_t max_map_points = 400000, size_t axes_every = 50);

}  // namespace quasiloc::app
