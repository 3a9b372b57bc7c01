#pragma once
// Map points for the tracker's point factor (the paper's P primitive): keypoints of the quasi-image, lifted to the
// map through its provenance, matched to the camera's keypoints by descriptor inside a small window around their
// projection at the aligned pose.
//
// Why only inside a small window: across the modality gap descriptors rarely agree (docs/experiments.md: at the true
// pose, 5.9 of 140 guided ORB candidates correct on simulated frames, 16.9 of 418 with the reflectivity matched to the
// camera's histogram). The tracker associates at the edge alignment's pose (about a centimetre off), so a
// window of a few pixels keeps the geometry in charge and leaves the descriptor to choose among the few keypoints
// left in it.
#include <Eigen/Geometry>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/estimation/measurements.h>
#include <quasiloc/frontend/features.h>
#include <quasiloc/frontend/point_matcher.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/quasi/quasi_image.h>
#include <vector>

namespace quasiloc::tracking
{
struct MapPointOptions
{
    double window_px = 3;       ///< a camera keypoint lies within this of the map point's projection
    double sigma_px = 1.5;      ///< the factor's pixel sigma
    double lift_radius_px = 2;  ///< provenance search around a quasi-image keypoint
};

/** Point factors: every keypoint of `quasi_features` (extracted on q) that lifts through q's provenance is
 *  projected with `camera` at T_world_cam and matched (matching: mutual nearest neighbour + ratio by descriptor)
 *  to the camera keypoints within window_px of that projection. Each match is a PointMatch (camera pixel, map
 *  point). */
std::vector<estimation::PointMatch> associateMapPoints(
    const frontend::Features& camera_features, const frontend::Features& quasi_features, const quasi::QuasiImage& q,
    const map::LidarMap& map, const core::CameraModel& camera, const Eigen::Isometry3d& T_world_cam,
    const frontend::PointMatchingOptions& matching, const MapPointOptions& options);

/** How many matches' map points project within correct_px of their camera pixel at the true pose. */
int countCorrectMatches(const std::vector<estimation::PointMatch>& matches, const core::CameraModel& camera,
                        const Eigen::Isometry3d& T_world_cam_true, double correct_px = 3);
}  // namespace quasiloc::tracking
