#pragma once
// The estimator's own input structs (no dependency on the frontend: the tracker adapts the frontend's
// matches to these). Pixels are in the (distorted) image of the camera model given to the estimator;
// map quantities are in the map frame; query-side stereo points in the left camera frame.
#include <Eigen/Core>
#include <Eigen/StdVector>
#include <vector>

namespace quasiloc::estimation
{
/** A keypoint of the current image matched to a map point (through quasi-image provenance). */
struct PointMatch
{
    Eigen::Vector2d px = Eigen::Vector2d::Zero();
    Eigen::Vector3d p_map = Eigen::Vector3d::Zero();
    double sigma_px = 1.0;
};

/** One association hypothesis of an image line: the LiDAR support points of a map line. */
struct LineCandidate
{
    std::vector<Eigen::Vector3d> support_map;
    double probability = 1.0;  ///< p_ic; the candidates of a factor sum to 1
};

/** An image line l (homogeneous pixel line, l.head<2>() unit length so l^T [u; 1] is a distance in pixels)
 *  and its association distribution over map lines. */
struct LineFactorInput
{
    Eigen::Vector3d line_px = Eigen::Vector3d::UnitX();
    std::vector<LineCandidate> candidates;
    double sigma_px = 1.0;
};

/** One association hypothesis of a query-side planar patch: a map plane n^T P + d = 0 (|n| = 1). */
struct PlaneCandidate
{
    Eigen::Vector3d n_map = Eigen::Vector3d::UnitZ();
    double d = 0.0;
    double probability = 1.0;
};

/** Stereo points of the current frame (left camera frame) on one structure, against candidate map planes. */
struct PlaneFactorInput
{
    std::vector<Eigen::Vector3d> points_cam;
    std::vector<PlaneCandidate> candidates;
    double sigma_m = 0.02;
};

/** A temporal landmark: a stereo observation in the previous and in the current frame (both cameras). */
struct StereoObservation
{
    Eigen::Vector2d left_px = Eigen::Vector2d::Zero();
    Eigen::Vector2d right_px = Eigen::Vector2d::Zero();
};
struct TemporalLandmark
{
    Eigen::Vector3d p_map_guess = Eigen::Vector3d::Zero();  ///< initial value (e.g. stereo triangulation)
    StereoObservation previous, current;
    double sigma_px = 1.0;
};

/** One IMU sample (specific force and angular rate in the body frame). */
struct ImuMeasurement
{
    double t = 0;
    Eigen::Vector3d acc = Eigen::Vector3d::Zero();
    Eigen::Vector3d gyro = Eigen::Vector3d::Zero();
};

/** Index of the candidate with the largest probability (the nominal association); -1 if none. */
template <class Candidates>
int nominalCandidate(const Candidates& candidates)
{
    int best = -1;
    for (size_t c = 0; c < candidates.size(); ++c)
        if (best < 0 || candidates[c].probability > candidates[best].probability) best = static_cast<int>(c);
    return best;
}

}  // namespace quasiloc::estimation
