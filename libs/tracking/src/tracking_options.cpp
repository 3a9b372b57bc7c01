#include <quasiloc/core/error.h>
#include <quasiloc/tracking/tracking_options.h>

namespace quasiloc::tracking
{
using core::Range;

void InitializationOptions::declare(core::OptionTable& t)
{
    t.addEnum("init", init, {{"groundtruth", InitMode::GroundTruth}, {"global", InitMode::Global}},
              "the start: the first frames' ground truth, or global localization by geometry (no initial guess)");
    t.add("init_sigma_m", init_sigma_m, "m", Range::above(0), "uncertainty of a given start (groundtruth)");
    t.add("init_sigma_deg", init_sigma_deg, "deg", Range::above(0), "its rotation uncertainty");
    t.add("init_sigma_v", init_sigma_v, "m/s", Range::above(0), "its velocity uncertainty");
    t.add("init_velocity_interval_s", init_velocity_interval_s, "s", Range::above(0),
          "global: time between the two fixes that give the velocity");
    t.add("init_max_disagreement_deg", init_max_disagreement_deg, "deg", Range::above(0),
          "global: the fixes' relative rotation must agree with the bias-corrected gyroscope's");
    t.add("init_max_speed_m_s", init_max_speed_m_s, "m/s", Range::above(0), "global: faster pairs are rejected");
    t.add("init_global_sigma_m", init_global_sigma_m, "m", Range::above(0),
          "uncertainty of a start (or restart) by global localization");
    t.add("init_global_sigma_deg", init_global_sigma_deg, "deg", Range::above(0), "its rotation uncertainty");
    t.add("init_global_sigma_v", init_global_sigma_v, "m/s", Range::above(0), "its velocity uncertainty");
    t.add("static_initialization", static_initialization,
          "a platform standing still from the first IMU sample measures its gyroscope bias (static_initialization.h)");
    t.add("init_remembered_places", init_remembered_places, "", Range::atLeast(0),
          "global: places of earlier attempts refined against each frame; one explaining clearly more than the "
          "search's answer replaces it (0: none)");
    t.add("search_radius_m", search_radius_m, "m", Range::atLeast(0),
          "global: search only within this of search_center_m (a region of a large map); 0: the whole map");
    t.add("search_center_m", search_center_m, "m", Range::any(), "global: the region's centre, [x y z] in the map");
}

void MapFactorOptions::declare(core::OptionTable& t)
{
    t.add("direct_factor_sigma_px", direct_factor_sigma_px, "px", Range::above(0),
          "pixel sigma of the map-edge residuals in the window (direct_factor.h)");
    t.add("direct_factor_effective_points", direct_factor_effective_points, "", Range::above(0),
          "all edge residuals together count as this many independent observations");
    t.add("stereo_map_factor", stereo_map_factor,
          "the stereo points' distance to the map's surfaces as a factor (map_distance_factor.h)");
    t.add("stereo_map_sigma_m", stereo_map_sigma_m, "m", Range::above(0), "per point: the map's and the field's noise");
    t.add("stereo_disparity_sigma_px", stereo_disparity_sigma_px, "px", Range::atLeast(0),
          "per point: disparity noise, z^2 / (f b) times this in depth");
    t.add("stereo_map_effective_points", stereo_map_effective_points, "", Range::above(0),
          "all stereo points together count as this many independent observations");
    t.add("stereo_map_truncation_m", stereo_map_truncation_m, "m", Range::above(0),
          "points farther than this from the map do not pull (occluders, clutter)");
    t.add("stereo_map_truncation_sigmas", stereo_map_truncation_sigmas, "", Range::atLeast(0),
          "> 0: a point's truncation is at least this many of its own sigmas (stereo_map_sigma_m and its depth "
          "noise), so that far points, whose depth error exceeds stereo_map_truncation_m, still pull; 0: "
          "stereo_map_truncation_m for every point (off by default: measured on the simulated campus car only, "
          "docs/benchmarks.md)");
    t.add("stereo_map_sigma_along_normal", stereo_map_sigma_along_normal,
          "a point's depth noise counts along the map's normal only (times |ray . normal| at the predicted pose): a "
          "depth error moves a stereo point along its ray, so far points on the road or on a facade seen at a "
          "grazing angle lie off their surface by a small share of it and hold the camera's height, roll and pitch "
          "(off by default: measured on the simulated campus car only, docs/benchmarks.md)");
    t.add("along_track_range_m", along_track_range_m, "m", Range::atLeast(0),
          "> 0: on every frame with the stereo surface term, its points are shifted along the camera's horizontal "
          "viewing direction by up to this much on each side of the prediction and scored against the map; a clear, "
          "unique minimum away from the prediction (a wall ahead, a crossing street) measures the position along the "
          "street, which the truncated surface term cannot reach once the track has drifted along a straight street "
          "(along_track_search.h; 0: off, the default: measured on the simulated campus car only, docs/benchmarks.md)");
    t.add("along_track_step_m", along_track_step_m, "m", Range::above(0), "between the searched shifts");
    t.add("along_track_smooth_m", along_track_smooth_m, "m", Range::atLeast(0),
          "each shift's score is the mean of the scores of the shifts within this of it (a single shift's score is "
          "noisy: the best of many lies below the prediction's by chance)");
    t.add("along_track_sigma_m", along_track_sigma_m, "m", Range::above(0),
          "the found position's sigma along the searched direction");
    t.add("along_track_min_gain", along_track_min_gain, "", Range::atLeast(0),
          "chi-square (in stereo_map_effective_points observations) the best shift gains over the prediction and "
          "over every shift a metre or more from it");
    t.add("along_track_velocity_sigma_m_s", along_track_velocity_sigma_m_s, "m/s", Range::atLeast(0),
          "with a fix, the previous state's velocity along the direction widens by this (its position by the shift): "
          "the drift the fix found came from them");
    t.add("stereo_map_max_depth_m", stereo_map_max_depth_m, "m", Range::above(0), "farther stereo points are left out");
    t.addEnum("stereo_map_points", stereo_map_points,
              {{"dense", StereoMapPoints::Dense}, {"sparse", StereoMapPoints::Sparse}},
              "dense: the frame's SGBM cloud ([GeometricLocalization] stereo keys); sparse: the ORB stereo matches");
    t.add("map_lines", map_lines, "point-to-line map factors on keyframes (map_lines.h), reweighted by [Reweighting]");
    t.add("line_sigma_px", line_sigma_px, "px", Range::above(0), "a camera segment's offset sigma");
    t.add("line_window_sigmas", line_window_sigmas, "", Range::above(0),
          "association window: this many predicted pixel sigmas at the median map depth ...");
    t.add("line_window_min_px", line_window_min_px, "px", Range::above(0), "... clamped to [min, max]");
    t.add("line_window_max_px", line_window_max_px, "px", Range::above(0),
          "the cap binds: the association is made at the aligned pose");
    t.add("line_max_angle_deg", line_max_angle_deg, "deg", Range::strictlyBetween(0, 90),
          "a map line and a camera segment associate within this angle");
    t.add("line_max_candidates", line_max_candidates, "", Range::atLeast(1), "map lines per camera segment at most");
    t.add(
        "map_points", map_points,
        "point factors on keyframes: quasi-image keypoints matched by descriptor near their projection (map_points.h)");
    t.add("point_window_px", point_window_px, "px", Range::above(0),
          "a match lies within this of the map point's projection at the aligned pose");
    t.add("point_sigma_px", point_sigma_px, "px", Range::above(0), "a point factor's pixel sigma");
    t.addEnum("map_point_descriptor", map_point_descriptor,
              {{"orb", MapPointDescriptor::Orb}, {"orientation_field", MapPointDescriptor::OrientationField}},
              "orb: ORB of the quasi-image matched to the camera's ORB keypoints within point_window_px, factors "
              "in H_0; orientation_field: the camera image searched densely for each rank-equalised reflectivity "
              "corner by orientation field, ratio test, each camera observation with its distribution over nearby "
              "map points, as reweighted structural factors (crossmodal_points.h, docs/crossmodal_matching.md)");
    t.addEnum("point_field_channel", point_field.channel,
              {{"reflectivity", CrossModalChannel::Reflectivity}, {"depth_edges", CrossModalChannel::DepthEdges}},
              "orientation_field: the map channel, the rank-equalised reflectivity or the depth edges (for maps "
              "without intensities)");
    t.add("point_field_keypoints", point_field.keypoints, "", Range::atLeast(1),
          "orientation_field: map keypoints per keyframe at most");
    t.add("point_field_window_base_px", point_field.window_base_px, "px", Range::above(0),
          "orientation_field: search radius = this + f (sigma_rad + sigma_m / depth), the prediction's sigmas ...");
    t.add("point_field_window_max_px", point_field.window_max_px, "px", Range::above(0),
          "... at most this: the cap binds, the association is made at the aligned pose");
    t.add("point_field_ratio", point_field.ratio, "", Range::between(0.1, 1),
          "orientation_field: best / second best descriptor distance below this");
    t.add("point_field_candidates", point_field.max_candidates, "", Range::atLeast(1),
          "orientation_field: map points per camera observation at most (those the ratio test cannot rule out)");
    t.add("point_field_temperature", point_field.temperature, "", Range::above(0),
          "orientation_field: p_c ~ exp(-(d_c - d_best) / this), d the squared descriptor distance (unit vectors)");
    t.add("map_planes", map_planes,
          "point-to-plane factors with an association distribution on keyframes (map_planes.h)");
    t.add("plane_effective_points", plane_effective_points, "", Range::above(0),
          "all plane factors together count as this many independent observations");
    t.add("edge_trust_sigmas", edge_trust_sigmas, "", Range::atLeast(0),
          "the map edge term's weight on a keyframe is exp(-(d / this)^2 / 2), d [sigmas] = the square root of "
          "how much the stereo surface term's cost grows from the prediction to the edge optimum (edge_trust.h); "
          "0: always trusted");
}

void MapFactorOptions::check(const std::string& input) const
{
    checkRanges(input, "MapFactors");
    core::require(line_window_max_px >= line_window_min_px, input + ": [MapFactors] line_window_max_px",
                  "must be >= line_window_min_px");
}

void TrackerOptions::declare(core::OptionTable& t)
{
    t.add("map_updates", map_updates, "false: no map at all, the visual-inertial (or IMU-only) baselines");
    t.add("keyframe_every", keyframe_every, "frames", Range::atLeast(1), "a map alignment every N frames");
    t.add("model_downscale", model_downscale, "", Range::between(1, 4),
          "the map alignment renders the map at 1/N of the camera's resolution for its edge model (N divides "
          "DirectAlignment.model_block_px); 1 whenever map_points, map_lines or map_planes is on: they read the "
          "full-resolution quasi-image");
    t.addEnum("map_term", map_term, {{"auto", MapTerm::Auto}, {"factor", MapTerm::Factor}, {"none", MapTerm::None}},
              "map edges in the window: factor; none; auto = factor when the map's reflectivity varies and its "
              "surfaces are at most edge_map_max_thickness_m thick, else none");
    t.add("edge_map_max_thickness_m", edge_map_max_thickness_m, "m", Range::above(0),
          "map_term = auto: the edge term only on maps whose surfaces are this thin or thinner (median thickness "
          "of the map's surface patches, printed by map-import, map-build and quasiloc-track): an exact survey map "
          "is a few mm thick, a map fused from mobile LiDAR sweeps 1-3 cm, and on those the edge term turns the "
          "map's scatter into pose error");
    t.add("min_prior_sigma_m", min_prior_sigma_m, "m", Range::above(0),
          "the alignment's prior: the predicted sigma, at least this");
    t.add("min_prior_sigma_deg", min_prior_sigma_deg, "deg", Range::above(0), "the same for its rotation");
    t.add("max_correction_m", max_correction_m, "m", Range::above(0),
          "larger map corrections are rejected (the gate is 3 predicted sigmas when wider)");
    t.add("max_correction_deg", max_correction_deg, "deg", Range::above(0), "the same for the rotation");
    t.add("temporal_landmarks", temporal_landmarks, "stereo landmarks between consecutive frames (odometry)");
    t.add("temporal_window_px", temporal_window_px, "px", Range::above(0),
          "a current keypoint's match lies within this of the previous one (temporal_predicted_window: of where the "
          "IMU prediction moves it)");
    t.add("temporal_predicted_window", temporal_predicted_window,
          "the temporal matching window is centred where the IMU's predicted camera motion moves each previous "
          "keypoint (its stereo point; without one, its direction), not on the keypoint itself: a car at 10 m/s "
          "moves 1 m between frames at 10 Hz, and near points move hundreds of pixels (off by default: measured on "
          "the simulated campus car only, docs/benchmarks.md)");
    t.add("max_landmarks", max_landmarks, "", Range::atLeast(0), "temporal landmarks per frame at most");
    t.add("temporal_max_gap_s", temporal_max_gap_s, "s", Range::above(0),
          "no temporal landmarks between frames farther apart than this (dropped frames): the windowed matching "
          "assumes the small motion of consecutive frames; two frame periods at 20 Hz: for a camera at 10 Hz or "
          "slower, raise it above the frame period");
    t.addEnum("stereo_matching", stereo_matching,
              {{"guided", StereoMatching::Guided}, {"descriptors", StereoMatching::Descriptors}},
              "the right image's match of a left keypoint: guided = searched around the frame's dense SGBM "
              "disparity (no features on the right image; needs MapFactors.stereo_map_points = dense, else the "
              "descriptors are used); descriptors = ORB on the right image too, matched along the epipolar band");
    t.add("zero_velocity_updates", zero_velocity_updates,
          "whenever the IMU's standstill detector (static_initialization.h) finds the last zero_velocity_span_s "
          "standing, the previous state's velocity is zero (a robot that stops; off by default: measured on the "
          "simulated ground robot, docs/benchmarks.md)");
    t.add("zero_velocity_span_s", zero_velocity_span_s, "s", Range::between(0.75, 10),
          "zero_velocity_updates: the IMU span the detector judges (a stop is seen this long after it begins; at "
          "least three of the detector's 0.25 s blocks)");
    t.add("zero_velocity_sigma_m_s", zero_velocity_sigma_m_s, "m/s", Range::above(0),
          "zero_velocity_updates: the standing velocity's sigma per axis (the sway of a standing platform)");
    t.add("zero_velocity_max_motion_px", zero_velocity_max_motion_px, "px", Range::above(0),
          "zero_velocity_updates: the image must agree, the median motion of the keypoints followed over at least "
          "10 frames at most this since their first sighting (an IMU cannot tell standing from a steady straight run)");
    t.add("standstill_end_motion_px", standstill_end_motion_px, "px", Range::above(0),
          "the start's standstill (static_initialization) ends when the image moves: the keypoints' median motion "
          "from one frame to the next, or since the first sighting of those followed over 3 or 10 frames, above "
          "this (a start or a restart during a steady run reads as standing to the IMU; a standing camera's "
          "keypoints jump by their pyramid level's grid step, 1-1.7 px)");
    t.add("guided_patch_radius_px", guided.patch_radius_px, "px", Range::between(1, 15),
          "guided matching: the compared patches are (2 r + 1)^2 pixels of the rectified pair");
    t.add("guided_search_px", guided.search_px, "px", Range::between(1, 20),
          "guided matching: columns searched on each side of the SGBM disparity (full resolution)");
    t.add("guided_max_prior_spread_px", guided.max_prior_spread_px, "px", Range::atLeast(0),
          "guided matching: SGBM disparities around the keypoint that differ more mark a depth edge (no point)");
    t.add("guided_max_mean_abs_diff", guided.max_mean_abs_diff, "", Range::above(0),
          "guided matching: the patches' mean absolute difference per pixel, each patch's mean removed, at most "
          "(gray levels)");
    t.add("concurrent_stages", concurrent_stages,
          "a frame's independent tasks (edge field, stereo points, dense stereo) on a worker thread and the tracking "
          "thread");
}

void TrackingRunOptions::declare(core::OptionTable& t)
{
    t.add("input_rawlog", input_rawlog, "the stereo + IMU rawlog to track (required)");
    t.add("calibration_ini", calibration_ini, "the rig and [imu] (dataset/calibration.h; required)");
    t.add("map_file", map_file, "the LiDAR map (map-import's or sim-rawlog's; required)");
    t.add("groundtruth", groundtruth, "TUM of T_world_cam0: the start for init = groundtruth, and the error table");
    t.add("output_dir", output_dir, "trajectory.tum, diagnostics.csv, summary.json, ... are written here");
    t.add("max_frames", max_frames, "frames", Range::atLeast(0), "stop after this many frames (0: all)");
    t.add("write_scene", write_scene, "also scene.3Dscene (map, ground truth, estimate) for SceneViewer3D");
    TrackerOptions::declare(t);
}

void RelocalizationOptions::declare(core::OptionTable& t)
{
    t.add("relocalize", relocalize, "check the track against the stereo geometry and relocalize when lost");
    t.add("relocalize_latest_only", relocalize_latest_only,
          "the search attempts the newest waiting frame (real time); false: every frame in order (reproducible)");
    t.add("relocalize_near_m", relocalize_near_m, "m", Range::atLeast(0),
          "search within this of the last confirmed pose (plus the speed below); 0: the whole map");
    t.add("relocalize_speed_m_s", relocalize_speed_m_s, "m/s", Range::atLeast(0),
          "the search sphere grows by this per second since the last confirmed pose");
    t.add("relocalize_single_fix", relocalize_single_fix,
          "restart at the first fix with the track's velocity; false: wait for a pair checked by the gyroscope");
    t.add("relocalize_heading_margin_deg", relocalize_heading_margin_deg, "deg", Range::atLeast(0),
          "the search looks only at headings within this of the orientation of the last verified frame (carried "
          "on by the gyroscope), plus three gyroscope-bias sigmas over the time since; 0: every heading");
    t.add("relocalize_heading_for_s", relocalize_heading_for_s, "s", Range::atLeast(0),
          "the heading prior holds this long after the loss (a verified pose can be wrong); then every heading is "
          "searched");
    t.add("relocalize_odometry_drift_ratio", relocalize_odometry_drift_ratio, "", Range::atLeast(0),
          "while lost, each frame is searched within three uncertainties of where the odometry puts it "
          "(odometry_while_lost's track), its uncertainty being relocalize_odometry_floor_m plus this share of the "
          "path since the last verified frame, and an ambiguous fix is taken at the one place within one uncertainty "
          "when every other lies beyond two; no prediction once the lost track moves faster than [Initialization] "
          "init_max_speed_m_s (diverged); 0: off (the sphere of relocalize_near_m). Needs [TrackMonitor] "
          "odometry_while_lost");
    t.add("relocalize_odometry_floor_m", relocalize_odometry_floor_m, "m", Range::atLeast(0.01),
          "the odometry prediction's uncertainty at the last verified frame (its own error and the doubtful frames "
          "before the loss)");
}

void TrackMonitorOptions::declare(core::OptionTable& t)
{
    t.add("stereo_check_max_sigmas", stereo_check_max_sigmas, "", Range::atLeast(0),
          "keyframes: when the stereo points' median distance to the map at the edge-aligned pose is above this many "
          "point sigmas, the stereo disagrees with the map (left/right desync, broken calibration): its factors are "
          "left out and the frame is unverified; 0: no check");
    t.add("stereo_check_release_sigmas", stereo_check_release_sigmas, "", Range::above(0),
          "after a rejection the bound is this until the stereo has agreed with the map for stereo_check_hold_s "
          "(a desync's effect comes and goes with the rotation rate)");
    t.add("stereo_check_hold_s", stereo_check_hold_s, "s", Range::atLeast(0),
          "... meanwhile the frames are unverified and the loss check, which weighs the same stereo, does not run");
    t.add("stereo_check_min_edge_ratio", stereo_check_min_edge_ratio, "", Range::atLeast(0),
          "the check trusts the edge-aligned pose only when its inlier ratio is at least this share of the usual one "
          "(aligned from a wrong pose the edges fit worse: then the stereo is believed)");
    t.add("usual_edge_ratio_weight", usual_edge_ratio_weight, "", Range::strictlyBetween(0, 1),
          "the usual edge inlier ratio and stereo distance to the map are running means over the frames whose stereo "
          "agreed, the newest weighing this");
    t.add(
        "stereo_drift_ratio", stereo_drift_ratio, "", Range::atLeast(0),
        "a frame whose stereo lies this many times farther from the map than usual (in point sigmas, the same "
        "running mean) is unverified and every check aligns the stereo until one passes: a pose drifting where "
        "the check's explained share stays high (along a corridor) is found; 0: no watch (the default: measured on the "
        "simulated ground robot only, docs/benchmarks.md)");
    t.add("check_every", check_every, "frames", Range::atLeast(1), "the geometry check of the tracked pose");
    t.add("lost_explained_ratio", lost_explained_ratio, "", Range::fromUpTo(0, 1),
          "a check that explains this share of the stereo points confirms the pose");
    t.add("lost_min_gain", lost_min_gain, "", Range::above(0),
          "below it, the check fails when aligning the points to the map explains this much more ...");
    t.add("lost_explained_floor", lost_explained_floor, "", Range::between(0, 1),
          "... or when the share is below this");
    t.add("input_gap_s", input_gap_s, "s", Range::above(0),
          "a gap between frames or in the IMU longer than this (or a rejected frame) leaves the track unverified, "
          "checked on every frame, until a check confirms it");
    t.add("lost_after_failed_checks", lost_after_failed_checks, "checks", Range::atLeast(1),
          "this many failed checks in a row mark the track lost");
    t.add("lost_after_misses", lost_after_misses, "frames", Range::atLeast(1),
          "this many rejected map alignments in a row mark the track lost");
    t.add("odometry_while_lost", odometry_while_lost,
          "while lost, frames are tracked by odometry alone (IMU and stereo landmarks, no map term): the map terms at "
          "a doubtful pose pull the track, and the search's prior, into a wrong place (off by default: measured on the "
          "simulated ground robot only)");
    t.add("lost_unconfirmed_restart_s", lost_unconfirmed_restart_s, "s", Range::atLeast(0),
          "a restart at a fix that no check has confirmed after this long is a loss (a single fix in a view that "
          "explains many places can be the wrong one, and the stereo of that view then passes every check); 0: never "
          "(the default: measured on the simulated ground robot only)");
    t.add("lost_velocity_random_walk", lost_velocity_random_walk, "m/s/sqrt(s)", Range::atLeast(0),
          "while lost, the tracker's velocity variance grows by this squared per second (a lost track's velocity may "
          "have diverged, and a velocity surer than it is makes the stereo landmarks outliers); 0: off (the default: "
          "measured on the simulated ground robot only)");
    t.add("stereo_hold_max_s", stereo_hold_max_s, "s", Range::atLeast(0),
          "a stereo hold (stereo_check_hold_s, renewed by every rejected frame) that has lasted this long makes the "
          "loss check due on every frame: it ends when a check confirms the pose (the stereo is released) or in a "
          "loss; 0: no bound (the default: measured on the simulated ground robot only)");
    t.add("stereo_hold_fit_below", stereo_hold_fit_below, "", Range::between(0, 1),
          "a rejected stereo is held only when it fits the map nowhere near: the loss check runs on the first rejected "
          "frame and, when this share or more of the stereo is explained (at the tracked pose or aligned from it), "
          "the stereo is sound and the pose is what disagrees: no hold, the stereo is not gated for "
          "stereo_check_hold_s, and the check's verdict stands; 0: every rejection holds");
}

void TrackMonitorOptions::check(const std::string& input) const
{
    checkRanges(input, "TrackMonitor");
    core::require(lost_explained_floor <= lost_explained_ratio, input + ": [TrackMonitor] lost_explained_floor",
                  "must be <= lost_explained_ratio");
}

}  // namespace quasiloc::tracking
