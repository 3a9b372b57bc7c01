#pragma once
// The tracking options, one struct per INI section, each key declared once (core/declared_options.h):
//   [Tracking]        the tracker: map updates, their gate, the temporal landmarks (TrackerOptions)
//   [Initialization]  the start: given or by global localization, its uncertainty, static initialization
//   [MapFactors]      the map's factors in the window: edges, stereo points against surfaces, lines, points, planes
//   [TrackMonitor]    the policy of the track's health: the stereo gate, the loss check, losses (TrackMonitor)
//   [Relocalization]  the relocalization search (TrackingSession)
// docs/options.md lists every key with its unit, range, default and documentation; docs/experiments.md the
// measurements behind the defaults.
#include <quasiloc/core/declared_options.h>
#include <quasiloc/tracking/crossmodal_points.h>
#include <quasiloc/tracking/guided_stereo_options.h>

#include <string>

namespace quasiloc::tracking
{
/** What carries the map's edges into the window. */
enum class MapTerm
{
    Auto,    ///< Factor when the map's reflectivity varies and its surfaces are thin (an exact map), else None
    Factor,  ///< the edge residuals as a window factor, linearised from the alignment's pose (direct_factor.h)
    None     ///< no edge alignment (the stereo surface factor alone)
};

enum class InitMode
{
    GroundTruth,  ///< the first frames' ground truth gives the pose and velocity
    Global        ///< global localization by geometry of two frames and the IMU between them
};

/** How the right image's match of a left keypoint is found (the temporal landmarks' stereo points). */
enum class StereoMatching
{
    Guided,      ///< around the frame's dense SGBM disparity, patches along the rectified row (guided_stereo.h)
    Descriptors  ///< ORB on the right image too, matched by descriptor along the epipolar band (stereo_matcher.h)
};

/** How map points are associated with the camera image (map_points). */
enum class MapPointDescriptor
{
    Orb,              ///< ORB of the quasi-image's gray image against the camera's ORB keypoints (map_points.h)
    OrientationField  ///< the camera against the rank-equalised reflectivity by orientation field (crossmodal_points.h)
};

/** Which stereo points the surface factor uses. */
enum class StereoMapPoints
{
    Dense,  ///< the frame's SGBM cloud (reloc/stereo_cloud.h)
    Sparse  ///< the ORB stereo matches of the temporal landmarks
};

struct InitializationOptions : public core::DeclaredOptions
{
    InitMode init = InitMode::Global;
    double init_sigma_m = 0.01, init_sigma_deg = 0.1, init_sigma_v = 0.05;
    double init_velocity_interval_s = 0.5, init_max_disagreement_deg = 2.0, init_max_speed_m_s = 4.0;
    double init_global_sigma_m = 0.05, init_global_sigma_deg = 1.0, init_global_sigma_v = 0.15;
    bool static_initialization = true;
    int init_remembered_places = 3;  ///< global_initialization.h: earlier attempts' places rescored per frame
    /** A region the global start searches (large maps): within search_radius_m of search_center_m (world). */
    Eigen::Vector3d search_center_m = Eigen::Vector3d::Zero();
    double search_radius_m = 0;
    void declare(core::OptionTable& t) override;
};

struct MapFactorOptions : public core::DeclaredOptions
{
    double direct_factor_sigma_px = 2.0, direct_factor_effective_points = 25;
    bool stereo_map_factor = true;
    double stereo_map_sigma_m = 0.02, stereo_disparity_sigma_px = 0.5, stereo_map_effective_points = 50;
    double stereo_map_truncation_m = 0.15, stereo_map_max_depth_m = 6;
    double stereo_map_truncation_sigmas = 0;
    bool stereo_map_sigma_along_normal = false;
    /** along_track_search.h: the frame's stereo points searched along the street against the map (0: off). */
    double along_track_range_m = 0, along_track_step_m = 0.1, along_track_sigma_m = 0.3, along_track_min_gain = 9;
    double along_track_velocity_sigma_m_s = 0.5, along_track_smooth_m = 0;
    StereoMapPoints stereo_map_points = StereoMapPoints::Dense;
    bool map_lines = false;
    double line_sigma_px = 1.5, line_window_sigmas = 3, line_window_min_px = 2, line_window_max_px = 3;
    double line_max_angle_deg = 5;
    int line_max_candidates = 3;
    bool map_points = false;
    double point_window_px = 3, point_sigma_px = 1.5;
    MapPointDescriptor map_point_descriptor = MapPointDescriptor::Orb;
    CrossModalPointOptions point_field;  ///< map_point_descriptor = orientation_field: the point_field_* keys
    bool map_planes = false;
    double plane_effective_points = 50;
    double edge_trust_sigmas = 0;  ///< edge_trust.h: the edge term's per-keyframe weight (0: always trusted)
    void declare(core::OptionTable& t) override;
    void check(const std::string& input) const;
};

struct TrackerOptions : public core::DeclaredOptions
{
    bool map_updates = true;
    int keyframe_every = 1;
    int model_downscale = 2;
    MapTerm map_term = MapTerm::Auto;
    /** map_term = auto: the edge term only on maps whose surfaces are at most this thick (map/surface_thickness.h).
     *  Reflectivity edges rendered from points scattered a centimetre or more across their surface move by pixels,
     *  and the edge term turns that into pose error (every real map and every swept map: docs/benchmarks.md). */
    double edge_map_max_thickness_m = 0.006;
    double min_prior_sigma_m = 0.05, min_prior_sigma_deg = 0.5;
    double max_correction_m = 0.15, max_correction_deg = 1.5;
    bool temporal_landmarks = true;
    double temporal_window_px = 60;
    bool temporal_predicted_window = false;
    double temporal_max_gap_s = 0.1;
    int max_landmarks = 150;
    bool zero_velocity_updates = false;
    double zero_velocity_span_s = 1.0, zero_velocity_sigma_m_s = 0.01, zero_velocity_max_motion_px = 1.0;
    double standstill_end_motion_px = 3.0;
    StereoMatching stereo_matching = StereoMatching::Guided;
    GuidedStereoOptions guided;  ///< stereo_matching = guided: the guided_* keys
    bool concurrent_stages = true;
    InitializationOptions initialization;  ///< [Initialization]
    MapFactorOptions factors;              ///< [MapFactors]
    void declare(core::OptionTable& t) override;
};

/** [Tracking] as a session reads it: the tracker's keys and the run's inputs and outputs. */
struct TrackingRunOptions : public TrackerOptions
{
    std::string input_rawlog, calibration_ini, map_file, groundtruth, output_dir = "out/track";
    int max_frames = 0;
    bool write_scene = true;
    void declare(core::OptionTable& t) override;
};

struct RelocalizationOptions : public core::DeclaredOptions
{
    bool relocalize = true;
    bool relocalize_latest_only = true;
    double relocalize_near_m = 0.5, relocalize_speed_m_s = 1.5;
    bool relocalize_single_fix = true;
    double relocalize_heading_margin_deg = 15, relocalize_heading_for_s = 5;
    double relocalize_odometry_drift_ratio = 0, relocalize_odometry_floor_m = 0.5;
    void declare(core::OptionTable& t) override;
};

/** Every threshold of the track monitor's policy (track_monitor.h): the stereo gate, the loss check, losses. */
struct TrackMonitorOptions : public core::DeclaredOptions
{
    double stereo_check_max_sigmas = 3, stereo_check_release_sigmas = 2, stereo_check_hold_s = 2;
    double stereo_check_min_edge_ratio = 0.8;
    double usual_edge_ratio_weight = 0.05;
    double stereo_drift_ratio = 0;
    int check_every = 5;
    double lost_explained_ratio = 0.7, lost_min_gain = 0.05, lost_explained_floor = 0.45;
    int lost_after_failed_checks = 2;
    int lost_after_misses = 20;
    double lost_unconfirmed_restart_s = 0;
    bool odometry_while_lost = false;
    double lost_velocity_random_walk = 0;
    double stereo_hold_max_s = 0;
    double stereo_hold_fit_below = 0;
    double input_gap_s = 0.15;  ///< three frame periods at 20 Hz
    void declare(core::OptionTable& t) override;
    void check(const std::string& input) const;
};

}  // namespace quasiloc::tracking
