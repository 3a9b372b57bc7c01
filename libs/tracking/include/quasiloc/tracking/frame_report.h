#pragma once
// What the tracker did on one frame: a row of the diagnostics CSV, and what the track monitor reads.
#include <Eigen/Geometry>
#include <cmath>

namespace quasiloc::tracking
{

/** What the tracker did on one frame (a row of the diagnostics CSV). */
struct FrameReport
{
    double t = 0;
    Eigen::Isometry3d T_world_cam0 = Eigen::Isometry3d::Identity();
    bool keyframe = false;
    bool map_update = false;                      ///< the map alignment was accepted as a measurement
    double correction_m = 0, correction_deg = 0;  ///< map alignment minus prediction
    double edge_inlier_ratio = 0;
    int edge_points = 0;
    double prior_sigma_m = 0, prior_sigma_deg = 0;
    int alignment_misses = 0;  ///< keyframes in a row whose map alignment was rejected (since the start)
    bool lost = false;         ///< the track monitor's: lost_after_misses misses in a row (TrackMonitor::lostByMisses)
    int landmarks = 0;
    int stereo_map_points = 0;  ///< stereo points in the map-distance factor
    /** How well the stereo agrees with the map, on keyframes with an accepted map alignment: the stereo points'
     *  median distance to the map's surfaces at the edge-aligned pose, in point sigmas (NaN: not measured). */
    double stereo_map_sigmas = NAN;
    /** The frame's stereo gate (stereo_gate.h, set by the track monitor) left the stereo's factors out: the stereo
     *  disagreed with the map (a left/right desync, a broken calibration). */
    bool stereo_rejected = false;
    int camera_lines = 0, map_lines = 0, line_factors = 0;  ///< map_lines: segments, lifted map lines, factors
    double line_candidates = 0;                             ///< mean candidates per line factor
    double line_window_px = 0;
    double ms_lines = 0;
    int quasi_keypoints = 0, point_factors = 0;  ///< map_points: the quasi-image's keypoints, point factors
    /** map_points: mean candidate map points per association (1 with ORB), and the associations whose (nominal)
     *  map point projects within 3 px of the camera pixel at the true pose (-1: no ground truth). */
    double point_candidates = 0;
    int point_correct = -1;
    double ms_points = 0;
    int plane_factors = 0;        ///< map_planes
    double plane_candidates = 0;  ///< mean candidates per plane factor
    double ms_planes = 0;
    Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero(), acc_bias = Eigen::Vector3d::Zero();  ///< estimated
    bool standing = false;  ///< the platform stands: since the start (static_initialization), or now, by the IMU
                            ///< (zero_velocity_updates); its velocity was set to zero
    /** Their marginal sigmas per axis after the frame (rad/s, m/s^2). */
    Eigen::Vector3d gyro_bias_sigma = Eigen::Vector3d::Zero(), acc_bias_sigma = Eigen::Vector3d::Zero();
    /** Wall times [ms]. ms_image: the camera edge field (on the tracking thread, after the render); ms_align:
     *  render, map model, edge field and LM, on the tracking thread, while the worker runs the stereo tasks;
     *  ms_visual: the wait for what is left of those (stereo points, dense stereo, their matching, segments) and
     *  the map factors on the points; ms_window: the window, of which ms_window_solve its Ceres solve and
     *  ms_window_marginal the marginal handed to the next frame; ms_total: the whole frame. */
    double ms_predict = 0, ms_image = 0, ms_align = 0, ms_visual = 0, ms_window = 0, ms_total = 0;
    double ms_window_solve = 0, ms_window_marginal = 0;
};

}  // namespace quasiloc::tracking
