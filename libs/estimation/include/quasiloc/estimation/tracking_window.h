#pragma once
// The tracking window: one Ceres problem over the previous and the current frame.
//
// WINDOW CHOICE. Two frames (previous + current) with the previous one's marginal as a prior. A map-based
// tracker has no drift to undo (every frame is tied to the map), so a long window buys little accuracy
// while costing time; two frames are exactly what the IMU preintegration (one interval) and the temporal
// stereo landmarks (seen in both) need. After the solve the previous frame and the landmarks are
// marginalised (Schur complement of the full window information, robust losses and weights applied at the
// final estimate) into a 15x15 Gaussian on the current state: the prior of the next window. Without a
// previous frame the window is the current pose alone with a pose prior (e.g. IMU prediction).
//
// FACTORS. Prior (15 or 6), IMU preintegration (9) + bias random walk (6), stereo reprojection of temporal
// landmarks in both frames (4 each; landmarks are variables), map-point reprojection (2), pose measurements
// of the current frame (6, robust: e.g. the direct map alignment), the direct edge term and the stereo points'
// distance to the map's surfaces (map_distance_factor.h) on the current frame, and the
// structural factors: point-to-line and point-to-plane, one Ceres block per factor using its NOMINAL
// candidate (argmax p_ic) with weight W*_i = w_i W_meas (w_i from the reweighting, applied as a ScaledLoss
// around the robust loss).
//
// REWEIGHTING ROUNDS. Each outer round: relinearise at the current estimate -> H_0 = marginal information
// of the current pose from all non-structural factors (prior, IMU, landmarks, map points; previous frame
// and landmarks Schur-complemented out) -> L = median camera depth of the map-point matches (or of the
// structural support points if there is none) -> H_ic = J_ic^T W_meas J_ic of every candidate -> w_i
// (reweighting.h) -> Levenberg-Marquardt with the weights held fixed. Rounds stop early when a round moves
// the current pose by less than 1e-6 (rad / m).
#include <mrpt/system/CTimeLogger.h>

#include <quasiloc/estimation/estimator_options.h>
#include <quasiloc/estimation/imu_preintegration.h>
#include <quasiloc/estimation/measurements.h>
#include <quasiloc/estimation/direct_alignment.h>
#include <quasiloc/map/distance_field.h>
#include <quasiloc/estimation/prior_factor.h>
#include <quasiloc/estimation/reweighting.h>
#include <quasiloc/estimation/visual_factors.h>
#include <vector>

namespace quasiloc::estimation
{
/** A direct measurement of the current pose (e.g. the direct map alignment's result), as a Gaussian. */
struct PoseMeasurement
{
    Eigen::Isometry3d T_map_body = Eigen::Isometry3d::Identity();
    Matrix6d information = Matrix6d::Identity();  ///< tangent order [dtheta; dp]
};

/** The direct map-edge term as a factor on the current pose (direct_factor.h) instead of a pose measurement: the
 *  field, camera and model must outlive the solve. Each of the model's n points gets sigma_px *
 *  sqrt(n / effective_points): the points' errors are correlated (one rendering, one pose), so together they count
 *  as `effective_points` independent pixel observations, not n. */
struct DirectEdgeTerm
{
    const CameraEdgeField* field = nullptr;
    const DirectAlignmentModel* model = nullptr;
    const core::CameraModel* camera = nullptr;
    double sigma_px = 2.0;
    double effective_points = 100;
    double truncation_px = 12, huber_px = 2;
};

/** The current frame's stereo points against the map's surfaces (map_distance_factor.h): the field must outlive
 *  the solve. Each point's sigma_m (stereo depth noise and the map's) is scaled by sqrt(n / effective_points). */
struct MapDistanceTerm
{
    const map::DistanceField* field = nullptr;
    std::vector<Eigen::Vector3d> p_cam;  ///< left camera frame
    std::vector<double> sigma_m;
    double effective_points = 50;
    double truncation_m = 0.15, huber_sigmas = 2;
};

struct WindowInput
{
    const StereoGeometry* stereo = nullptr;  ///< required; its left camera observes the map factors
    bool has_previous = false;
    FrameState previous;                     ///< initial value of the previous frame (has_previous)
    StatePrior prior;                        ///< on the previous frame if has_previous, else on the current one
    const ImuPreintegration* imu = nullptr;  ///< previous -> current (requires has_previous)
    FrameState current;                      ///< initial guess of the current frame (e.g. the IMU prediction)
    std::vector<PointMatch> points;
    std::vector<LineFactorInput> lines;
    std::vector<PlaneFactorInput> planes;
    std::vector<TemporalLandmark> landmarks;          ///< used only with a previous frame
    std::vector<PoseMeasurement> pose_measurements;   ///< on the current frame (map measurements: part of H_0)
    std::vector<DirectEdgeTerm> direct_terms;         ///< on the current frame (the left camera's image)
    std::vector<MapDistanceTerm> map_distance_terms;  ///< on the current frame (its stereo points)
};

struct WindowStats
{
    int rounds = 0;
    int lm_iterations = 0;
    double final_cost = 0;
    double L = 1.0;
    int structural_factors = 0;
    double linearize_ms = 0, reweight_ms = 0, solve_ms = 0, marginalize_ms = 0;
};

struct WindowResult
{
    FrameState previous, current;
    StatePrior marginal;            ///< Gaussian on the current state: the next window's prior
    ReweightingResult reweighting;  ///< of the last round
    WindowStats stats;
};

/** Solves the window. InputError for inconsistent input (no stereo geometry, IMU without previous frame,
 *  non-finite values). Returns false when Ceres reports no usable solution (the result then holds the
 *  initial guess). Stages are timed into `timer` when given. */
bool estimateWindow(const EstimatorOptions& options, const ReweightingOptions& reweighting, const WindowInput& input,
                    WindowResult& result, mrpt::system::CTimeLogger* timer = nullptr);

}  // namespace quasiloc::estimation
