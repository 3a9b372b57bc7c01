#pragma once
// A feature-metric score for bench_crossmodal's cost profile: does the DENSE feature map of the camera image agree
// with the quasi-image's where the map is seen, more at the true pose than beside it? Measured because keypoint
// matching between the two modalities finds ~0 correct pairs on KITTI while dense XFeat features still peak at
// the right place (a throwaway correlation of the two maps over image shifts found it first).
//
// Model (map side, from a quasi-image rendered at a pose): one 3D point per dense-map cell whose centre pixel has
// a depth, with the quasi-image's descriptor of that cell. Both maps are CENTRED (the mean descriptor of the map's
// valid cells subtracted, rows renormalised): raw XFeat descriptors share a large common component that makes any
// overlap look similar (mean cosine 0.49 off the peak vs 0.52 at it; centred 0.12 vs 0.17).
// Score(T) = mean over model points of the cosine between the point's descriptor and the camera map bilinearly
// interpolated (and renormalised: a blend of unit vectors is shorter, which would favour poses that put points on
// cell centres) at its projection; points outside the image count 0.
//
// Not a refinement method: a grid + pattern search maximising it (tried) ends 0.6-2 deg from the truth on KITTI
// and 0.5-0.8 deg on a simulated frame from (a): the score singles out the truth among its neighbours but its
// maximum over a search region is not precise enough (8 px cells).
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/frontend/features.h>
#include <vector>

namespace quasiloc::bench
{
/** A dense map with the mean row over `valid_cells` (all cells when empty) subtracted and rows renormalised. */
frontend::DenseMap centredDenseMap(const frontend::DenseMap& map, const std::vector<uint8_t>& valid_cells = {});

struct FeatureMetricModel
{
    std::vector<Eigen::Vector3d> points_world;
    cv::Mat descriptors;  ///< one CV_32F row per point (centred, unit)
};

/** Model from the quasi-image's dense map and completed depth/validity, rendered with `camera` at T_world_cam. */
FeatureMetricModel buildFeatureMetricModel(const frontend::DenseMap& quasi_dense, const cv::Mat& depth,
                                           const cv::Mat& valid, const core::CameraModel& camera,
                                           const Eigen::Isometry3d& T_world_cam);

/** The mean similarity above; camera_dense must be centred. */
double featureMetricScore(const frontend::DenseMap& camera_dense, const FeatureMetricModel& model,
                          const core::CameraModel& camera, const Eigen::Isometry3d& T_world_cam);

}  // namespace quasiloc::bench
