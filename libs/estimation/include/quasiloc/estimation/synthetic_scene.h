#pragma once
// Random single-frame scenes for tests and bench_estimation (no images): map points, map lines with LiDAR
// support, planes, and a camera; noisy observations; association distributions with wrong candidates;
// degenerate layouts. Everything is generated in the true camera frame and moved to the map frame by a
// random true pose, so no axis of the map is special.
//
// Layouts (camera looks along +z, y down, at the true pose):
//   Room:       a 5 x 3 x 9 m box (walls x = +-2.5, floor y = 1.5, ceiling y = -1.5, back wall z = 8),
//               door and window frames on the walls, points everywhere: well conditioned.
//   Corridor:   walls x = +-1.2, floor/ceiling y = +-1.2, 30 m long; few map points, all far; the long
//               edges run along z and the planes are parallel to z: translation along z is weak, only the
//               vertical door-frame lines and the far points observe it.
//   SingleWall: one wall z = 4 facing the camera with few points: in-plane translation is weak (coupled with
//               rotation), the wall's lines and plane patches carry the rest.
// Association: every line/plane factor has `candidates` hypotheses, the true structure and nearby wrong ones
// (a parallel copy of the line shifted by 0.15-0.5 m, or another edge; a parallel plane or another plane);
// with probability wrong_nominal_rate the largest p belongs to a wrong candidate.
#include <quasiloc/estimation/measurements.h>
#include <quasiloc/estimation/prior_factor.h>
#include <quasiloc/estimation/visual_factors.h>
#include <random>
#include <string>

namespace quasiloc::estimation
{
enum class SceneLayout
{
    Room,
    Corridor,
    SingleWall
};
std::string toString(SceneLayout layout);

struct SceneOptions
{
    SceneLayout layout = SceneLayout::Room;
    int num_points = 60;             ///< map-point matches (Room; the degenerate layouts use fewer)
    int num_lines = 20;              ///< structural line factors
    int num_planes = 6;              ///< structural plane factors (patches of stereo points)
    int candidates = 3;              ///< hypotheses per structural factor
    int support_points = 8;          ///< LiDAR points per map line
    int plane_points = 12;           ///< stereo points per plane patch
    double pixel_noise = 1.0;        ///< keypoint and line-endpoint noise, pixels
    double lidar_noise_m = 0.01;     ///< noise of map points and line support
    double stereo_noise_rel = 0.01;  ///< stereo point noise along the ray, relative to depth
    double point_outlier_rate = 0.05;
    double wrong_nominal_rate = 0.2;  ///< share of structural factors whose argmax is a wrong candidate
    double init_sigma_m = 0.05;       ///< the guess (IMU prediction) is truth (+) N(0, sigma); prior has this sigma
    double init_sigma_deg = 1.0;
    // Misspecification (what a real tracker lives with): the prior's stated sigma is the true one divided
    // by prior_overconfidence; map-point matches are noisier than their sigma_px by point_noise_factor
    // (keypoint vs rendered-pixel provenance), while their stated sigma stays pixel_noise.
    double prior_overconfidence = 1.0;
    double point_noise_factor = 1.0;
};

struct SyntheticFrame
{
    StereoGeometry stereo;  ///< 640x480, f = 400, 0.11 m baseline, body = left camera
    Eigen::Isometry3d T_map_body_true;
    FrameState guess;  ///< the initial value
    StatePrior prior;  ///< pose prior centred on the guess
    std::vector<PointMatch> points;
    std::vector<LineFactorInput> lines;
    std::vector<PlaneFactorInput> planes;
    int wrong_nominal_lines = 0, wrong_nominal_planes = 0;
};

/** A random frame; deterministic for the state of `rng`. The returned frame's stereo geometry is referenced
 *  by pointer by the factors built from it: keep the SyntheticFrame alive (and do not move it) while solving. */
SyntheticFrame makeSyntheticFrame(const SceneOptions& options, std::mt19937& rng);

}  // namespace quasiloc::estimation
