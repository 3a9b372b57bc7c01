#include <quasiloc/core/error.h>
#include <quasiloc/core/ini_read.h>
#include <quasiloc/tracking/tracker.h>

namespace quasiloc::tracking
{
void TrackerOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    using core::readIniDouble;
    map_updates = core::readIniBool(c, s, "map_updates", map_updates);
    keyframe_every = core::readIniInt(c, s, "keyframe_every", keyframe_every);
    direct_sigma_m = readIniDouble(c, s, "direct_sigma_m", direct_sigma_m);
    direct_sigma_deg = readIniDouble(c, s, "direct_sigma_deg", direct_sigma_deg);
    map_information = c.read_string(s, "map_information", map_information);
    map_term = c.read_string(s, "map_term", map_term);
    direct_factor_sigma_px = readIniDouble(c, s, "direct_factor_sigma_px", direct_factor_sigma_px);
    direct_factor_effective_points = readIniDouble(c, s, "direct_factor_effective_points", direct_factor_effective_points);
    min_prior_sigma_m = readIniDouble(c, s, "min_prior_sigma_m", min_prior_sigma_m);
    min_prior_sigma_deg = readIniDouble(c, s, "min_prior_sigma_deg", min_prior_sigma_deg);
    max_correction_m = readIniDouble(c, s, "max_correction_m", max_correction_m);
    max_correction_deg = readIniDouble(c, s, "max_correction_deg", max_correction_deg);
    lost_after_misses = core::readIniInt(c, s, "lost_after_misses", lost_after_misses);
    temporal_landmarks = core::readIniBool(c, s, "temporal_landmarks", temporal_landmarks);
    temporal_window_px = readIniDouble(c, s, "temporal_window_px", temporal_window_px);
    max_landmarks = core::readIniInt(c, s, "max_landmarks", max_landmarks);
    init_sigma_m = readIniDouble(c, s, "init_sigma_m", init_sigma_m);
    init_sigma_deg = readIniDouble(c, s, "init_sigma_deg", init_sigma_deg);
    init_sigma_v = readIniDouble(c, s, "init_sigma_v", init_sigma_v);
    concurrent_stages = core::readIniBool(c, s, "concurrent_stages", concurrent_stages);
    static_initialization = core::readIniBool(c, s, "static_initialization", static_initialization);
    init = c.read_string(s, "init", init);
    init_velocity_interval_s = readIniDouble(c, s, "init_velocity_interval_s", init_velocity_interval_s);
    init_max_disagreement_deg = readIniDouble(c, s, "init_max_disagreement_deg", init_max_disagreement_deg);
    init_max_speed_m_s = readIniDouble(c, s, "init_max_speed_m_s", init_max_speed_m_s);
    init_global_sigma_m = readIniDouble(c, s, "init_global_sigma_m", init_global_sigma_m);
    init_global_sigma_deg = readIniDouble(c, s, "init_global_sigma_deg", init_global_sigma_deg);
    init_global_sigma_v = readIniDouble(c, s, "init_global_sigma_v", init_global_sigma_v);
    stereo_map_factor = core::readIniBool(c, s, "stereo_map_factor", stereo_map_factor);
    stereo_map_sigma_m = readIniDouble(c, s, "stereo_map_sigma_m", stereo_map_sigma_m);
    stereo_disparity_sigma_px = readIniDouble(c, s, "stereo_disparity_sigma_px", stereo_disparity_sigma_px);
    stereo_map_effective_points = readIniDouble(c, s, "stereo_map_effective_points", stereo_map_effective_points);
    stereo_map_truncation_m = readIniDouble(c, s, "stereo_map_truncation_m", stereo_map_truncation_m);
    stereo_map_max_depth_m = readIniDouble(c, s, "stereo_map_max_depth_m", stereo_map_max_depth_m);
    stereo_map_points = c.read_string(s, "stereo_map_points", stereo_map_points);
    map_lines = core::readIniBool(c, s, "map_lines", map_lines);
    line_sigma_px = readIniDouble(c, s, "line_sigma_px", line_sigma_px);
    line_window_sigmas = readIniDouble(c, s, "line_window_sigmas", line_window_sigmas);
    line_window_min_px = readIniDouble(c, s, "line_window_min_px", line_window_min_px);
    line_window_max_px = readIniDouble(c, s, "line_window_max_px", line_window_max_px);
    line_max_angle_deg = readIniDouble(c, s, "line_max_angle_deg", line_max_angle_deg);
    line_max_candidates = core::readIniInt(c, s, "line_max_candidates", line_max_candidates);
    map_points = core::readIniBool(c, s, "map_points", map_points);
    point_window_px = readIniDouble(c, s, "point_window_px", point_window_px);
    point_sigma_px = readIniDouble(c, s, "point_sigma_px", point_sigma_px);
    map_planes = core::readIniBool(c, s, "map_planes", map_planes);
    plane_effective_points = readIniDouble(c, s, "plane_effective_points", plane_effective_points);
}

void TrackerOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    c.write(s, "map_updates", map_updates ? "true" : "false", 24, 10, "false: VIO / IMU-only baselines");
    c.write(s, "keyframe_every", keyframe_every, 24, 10, "map alignment every N frames");
    c.write(s, "direct_sigma_m", direct_sigma_m, 24, 10, "map-alignment measurement sigma");
    c.write(s, "direct_sigma_deg", direct_sigma_deg, 24, 10);
    c.write(s, "map_information", map_information, 24, 10, "fixed | observability (map_measurement.h)");
    c.write(s, "map_term", map_term, 24, 10,
            "auto (factor if the map has reflectivity, else none) | measurement | factor (direct_factor.h) | none");
    c.write(s, "direct_factor_sigma_px", direct_factor_sigma_px, 24, 10);
    c.write(s, "direct_factor_effective_points", direct_factor_effective_points, 24, 10);
    c.write(s, "min_prior_sigma_m", min_prior_sigma_m, 24, 10, "alignment prior: predicted sigma, at least this");
    c.write(s, "min_prior_sigma_deg", min_prior_sigma_deg, 24, 10);
    c.write(s, "max_correction_m", max_correction_m, 24, 10, "larger map corrections are rejected");
    c.write(s, "max_correction_deg", max_correction_deg, 24, 10);
    c.write(s, "lost_after_misses", lost_after_misses, 24, 10, "consecutive rejected keyframes: lost");
    c.write(s, "temporal_landmarks", temporal_landmarks ? "true" : "false", 24, 10, "stereo landmarks between frames");
    c.write(s, "temporal_window_px", temporal_window_px, 24, 10);
    c.write(s, "max_landmarks", max_landmarks, 24, 10);
    c.write(s, "init_sigma_m", init_sigma_m, 24, 10, "initial state uncertainty");
    c.write(s, "init_sigma_deg", init_sigma_deg, 24, 10);
    c.write(s, "init_sigma_v", init_sigma_v, 24, 10);
    c.write(s, "concurrent_stages", concurrent_stages ? "true" : "false", 24, 10, "independent stages in parallel");
    c.write(s, "static_initialization", static_initialization ? "true" : "false", 24, 10,
            "gyroscope bias from a standing start");
    c.write(s, "init", init, 24, 10, "groundtruth | global (global localization by geometry)");
    c.write(s, "init_velocity_interval_s", init_velocity_interval_s, 24, 10, "global: time between the two fixes");
    c.write(s, "init_max_disagreement_deg", init_max_disagreement_deg, 24, 10, "global: fixes vs gyroscope");
    c.write(s, "init_max_speed_m_s", init_max_speed_m_s, 24, 10);
    c.write(s, "init_global_sigma_m", init_global_sigma_m, 24, 10, "global: uncertainty of the start");
    c.write(s, "init_global_sigma_deg", init_global_sigma_deg, 24, 10);
    c.write(s, "init_global_sigma_v", init_global_sigma_v, 24, 10);
    c.write(s, "stereo_map_factor", stereo_map_factor ? "true" : "false", 24, 10, "stereo points vs map surfaces");
    c.write(s, "stereo_map_sigma_m", stereo_map_sigma_m, 24, 10);
    c.write(s, "stereo_disparity_sigma_px", stereo_disparity_sigma_px, 24, 10);
    c.write(s, "stereo_map_effective_points", stereo_map_effective_points, 24, 10);
    c.write(s, "stereo_map_truncation_m", stereo_map_truncation_m, 24, 10);
    c.write(s, "stereo_map_max_depth_m", stereo_map_max_depth_m, 24, 10);
    c.write(s, "stereo_map_points", stereo_map_points, 24, 10, "sparse (ORB stereo matches) | dense (SGBM cloud)");
    c.write(s, "map_lines", map_lines ? "true" : "false", 24, 10, "point-to-line map factors (map_lines.h)");
    c.write(s, "line_sigma_px", line_sigma_px, 24, 10);
    c.write(s, "line_window_sigmas", line_window_sigmas, 24, 10, "association window from the pose covariance");
    c.write(s, "line_window_min_px", line_window_min_px, 24, 10);
    c.write(s, "line_window_max_px", line_window_max_px, 24, 10);
    c.write(s, "line_max_angle_deg", line_max_angle_deg, 24, 10);
    c.write(s, "line_max_candidates", line_max_candidates, 24, 10);
    c.write(s, "map_points", map_points ? "true" : "false", 24, 10, "point factors (map_points.h)");
    c.write(s, "point_window_px", point_window_px, 24, 10, "around the map point's projection at the aligned pose");
    c.write(s, "point_sigma_px", point_sigma_px, 24, 10);
    c.write(s, "map_planes", map_planes ? "true" : "false", 24, 10, "point-to-plane factors (map_planes.h)");
    c.write(s, "plane_effective_points", plane_effective_points, 24, 10, "all plane factors count as this many");
}

void TrackerOptions::check(const std::string& input) const
{
    const std::string k = input + ": [Tracking] ";
    core::require(keyframe_every >= 1, k + "keyframe_every", "must be >= 1");
    core::require(line_sigma_px > 0 && line_window_sigmas > 0, k + "line_sigma_px/line_window_sigmas", "must be > 0");
    core::require(line_window_min_px > 0 && line_window_max_px >= line_window_min_px, k + "line_window_min/max_px",
                  "need 0 < min <= max");
    core::require(line_max_angle_deg > 0 && line_max_angle_deg < 90, k + "line_max_angle_deg", "must be in (0, 90)");
    core::require(line_max_candidates >= 1, k + "line_max_candidates", "must be >= 1");
    core::require(point_window_px > 0 && point_sigma_px > 0, k + "point_window_px/point_sigma_px", "must be > 0");
    core::require(plane_effective_points > 0, k + "plane_effective_points", "must be > 0");
    core::require(direct_sigma_m > 0 && direct_sigma_deg > 0, k + "direct_sigma_m/deg", "must be > 0");
    core::require(map_information == "fixed" || map_information == "observability", k + "map_information",
                  "'" + map_information + "' is not fixed or observability");
    core::require(map_term == "auto" || map_term == "measurement" || map_term == "factor" || map_term == "none",
                  k + "map_term", "'" + map_term + "' is not auto, measurement, factor or none");
    core::require(direct_factor_sigma_px > 0 && direct_factor_effective_points > 0,
                  k + "direct_factor_sigma_px/effective_points", "must be > 0");
    core::require(min_prior_sigma_m > 0 && min_prior_sigma_deg > 0, k + "min_prior_sigma_m/deg", "must be > 0");
    core::require(max_correction_m > 0 && max_correction_deg > 0, k + "max_correction_m/deg", "must be > 0");
    core::require(lost_after_misses >= 1, k + "lost_after_misses", "must be >= 1");
    core::require(temporal_window_px > 0, k + "temporal_window_px", "must be > 0");
    core::require(max_landmarks >= 0, k + "max_landmarks", "must be >= 0");
    core::require(init_sigma_m > 0 && init_sigma_deg > 0 && init_sigma_v > 0,
                  k + "init_sigma_*", "must be > 0");
    core::require(stereo_map_points == "sparse" || stereo_map_points == "dense", k + "stereo_map_points",
                  "'" + stereo_map_points + "' is not sparse or dense");
    core::require(init == "groundtruth" || init == "global", k + "init", "'" + init + "' is not groundtruth or global");
    core::require(init_velocity_interval_s > 0 && init_max_disagreement_deg > 0 && init_max_speed_m_s > 0,
                  k + "init_velocity_interval_s/max_disagreement_deg/max_speed_m_s", "must be > 0");
    core::require(init_global_sigma_m > 0 && init_global_sigma_deg > 0 && init_global_sigma_v > 0,
                  k + "init_global_sigma_*", "must be > 0");
    core::require(stereo_map_sigma_m > 0 && stereo_disparity_sigma_px >= 0 && stereo_map_effective_points > 0 &&
                      stereo_map_truncation_m > 0 && stereo_map_max_depth_m > 0,
                  k + "stereo_map_*", "sigmas, effective points, truncation and depth must be > 0");
}

}  // namespace quasiloc::tracking
