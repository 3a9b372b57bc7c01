#pragma once
// Map points for the tracker's point factor, associated across the camera/LiDAR gap by structure: the camera image
// against the quasi-image's rank-equalised reflectivity, both described by the orientation field of their gradients
// (sign ignored, magnitude normalised locally: crossmodal_descriptors.h), searched densely within a window the pose's
// uncertainty predicts, kept by a ratio test. docs/crossmodal_matching.md measures this combination (the most precise
// on the simulator; on real KITTI frames no descriptor beats chance).
//
// Association, per map keypoint (a Shi-Tomasi corner of the map channel, by default the rank-equalised
// reflectivity, on a pixel a map point won,
// lifted through the quasi-image's provenance to that map point P0, projected at the aligned pose to u0):
//  1. every camera pixel of the square window of radius r around u0 is a candidate; the best u* is kept when its
//     distance is below ratio x the best candidate farther than 3 px from it (the measured rule);
//  2. the candidate distribution of the camera observation u*: every map point at its own quasi-image pixel within r
//     of u* (at the aligned pose) is compared with the camera descriptor at u*; the local minima of that distance
//     (3 px apart) that the ratio test could not rule out (distance <= best / ratio^2), at most max_candidates,
//     are the candidates, with p_c proportional to exp(-(d_c - d_best) / temperature) (d: squared descriptor
//     distance of unit vectors). The nominal candidate is the most probable one, not necessarily P0.
// The estimator takes an association as two point-to-line factors through u*, one per image axis: l = (1, 0, -u)
// and (0, 1, -v) give the reprojection residual's two components exactly, and as structural factors they carry the
// candidate distribution into the reweighting (reweighting.h). Unlike ORB map points they are not part of H_0.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/estimation/measurements.h>
#include <quasiloc/frontend/crossmodal_descriptors.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/quasi/quasi_image.h>
#include <vector>

namespace quasiloc::tracking
{
/** The quasi-image channel the camera is matched against. */
enum class CrossModalChannel
{
    Reflectivity,  ///< rank-equalised per log-depth band (the measured choice)
    DepthEdges     ///< the depth-edge channel: for maps without intensities (a GMM's constant 0.5)
};

struct CrossModalPointOptions
{
    CrossModalChannel channel = CrossModalChannel::Reflectivity;
    int keypoints = 150;                   ///< map keypoints per keyframe at most
    double min_keypoint_distance_px = 10;  ///< between map keypoints
    double min_valid_share = 0.8;          ///< of a map keypoint's descriptor footprint
    double window_base_px = 8;             ///< search radius r = base + f (sigma_rad + sigma_m / depth) ...
    double window_max_px = 10;             ///< ... at most this
    double ratio = 0.9;                    ///< best / second best distance (unsquared)
    int max_candidates = 4;                ///< map points per camera observation at most (1: single hypothesis)
    double temperature = 0.1;              ///< of the candidate probabilities, in squared descriptor distance
    int depth_bands = 4;                   ///< rank equalisation per log-depth band
    double fill_sigma_px = 3;              ///< holes of the quasi-image filled before describing
    double depth_edge_sigma_px = 3, depth_edge_scale = 0.1;  ///< channel = depth edges (crossmodal_descriptors.h)
    frontend::CrossModalDescriptorOptions descriptors;
};

/** One camera observation and the map points it may show. */
struct CrossModalPointAssociation
{
    Eigen::Vector2d px = Eigen::Vector2d::Zero();          ///< u*, the camera pixel
    Eigen::Vector3d p_searched = Eigen::Vector3d::Zero();  ///< P0, the map point whose search found u*
    std::vector<Eigen::Vector3d> p_map;                    ///< candidates
    std::vector<double> probability;                       ///< sum to 1
    int nominal() const;                                   ///< argmax probability
};

struct CrossModalPointStats
{
    int map_keypoints = 0;  ///< lifted map keypoints searched
    int accepted = 0;       ///< passed the ratio test
};

/** The camera side: the orientation field of the camera's gray image (computed once per keyframe). */
frontend::DescriptorField describeCameraForMapPoints(const cv::Mat& gray, const CrossModalPointOptions& o);

/** Associations of the quasi-image q (rendered near T_world_cam) with the camera field, at the aligned pose
 *  T_world_cam; the window from the pose's sigmas (sigma_m, sigma_rad). */
std::vector<CrossModalPointAssociation> associateCrossModalPoints(const frontend::DescriptorField& camera_field,
                                                                  const quasi::QuasiImage& q, const map::LidarMap& map,
                                                                  const core::CameraModel& camera,
                                                                  const Eigen::Isometry3d& T_world_cam, double sigma_m,
                                                                  double sigma_rad, const CrossModalPointOptions& o,
                                                                  CrossModalPointStats* stats = nullptr);

/** Two point-to-line factors per association (the image axes through u*), candidates and probabilities kept. */
void appendAxisLineFactors(const std::vector<CrossModalPointAssociation>& associations, double sigma_px,
                           std::vector<estimation::LineFactorInput>& lines);

/** How many associations' nominal candidate projects within correct_px of u* at the true pose. */
int countCorrect(const std::vector<CrossModalPointAssociation>& associations, const core::CameraModel& camera,
                 const Eigen::Isometry3d& T_world_cam_true, double correct_px = 3);

}  // namespace quasiloc::tracking
