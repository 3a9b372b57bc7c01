// INI loading, saving and checking of the sim library's option structs (one place for all key names).
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/sim/lidar_sampler.h>
#include <quasiloc/sim/stereo_renderer.h>
#include <quasiloc/sim/world_builder.h>

namespace quasiloc::sim
{
namespace
{
void requireRange(double v, double lo, double hi, const std::string& input)
{
    core::require(std::isfinite(v) && v >= lo && v <= hi, input,
                  "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + std::to_string(v));
}
}  // namespace

void WorldOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    MRPT_LOAD_CONFIG_VAR(world, string, c, s);
    MRPT_LOAD_CONFIG_VAR(gmm_patches, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(gmm_sigma_scale, double, c, s);
    MRPT_LOAD_CONFIG_VAR(gmm_min_semi_axis_m, double, c, s);
    MRPT_LOAD_CONFIG_VAR(gmm_max_semi_axis_m, double, c, s);
    MRPT_LOAD_CONFIG_VAR(shell_margin_m, double, c, s);
    MRPT_LOAD_CONFIG_VAR(num_boxes, int, c, s);
    MRPT_LOAD_CONFIG_VAR(num_slabs, int, c, s);
    MRPT_LOAD_CONFIG_VAR(num_poles, int, c, s);
    MRPT_LOAD_CONFIG_VAR(num_wall_posters, int, c, s);
    MRPT_LOAD_CONFIG_VAR(clearance_m, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_cell_m, double, c, s);
    MRPT_LOAD_CONFIG_VAR(num_lights, int, c, s);
    MRPT_LOAD_CONFIG_VAR(light_intensity, double, c, s);
    MRPT_LOAD_CONFIG_VAR(ambient, double, c, s);
    MRPT_LOAD_CONFIG_VAR(texture_size_px, int, c, s);
    MRPT_LOAD_CONFIG_VAR(shadow_map_px, int, c, s);
}

void WorldOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    MRPT_SAVE_CONFIG_VAR(world, c, s);
    MRPT_SAVE_CONFIG_VAR(gmm_patches, c, s);
    MRPT_SAVE_CONFIG_VAR(gmm_sigma_scale, c, s);
    MRPT_SAVE_CONFIG_VAR(gmm_min_semi_axis_m, c, s);
    MRPT_SAVE_CONFIG_VAR(gmm_max_semi_axis_m, c, s);
    MRPT_SAVE_CONFIG_VAR(shell_margin_m, c, s);
    MRPT_SAVE_CONFIG_VAR(num_boxes, c, s);
    MRPT_SAVE_CONFIG_VAR(num_slabs, c, s);
    MRPT_SAVE_CONFIG_VAR(num_poles, c, s);
    MRPT_SAVE_CONFIG_VAR(num_wall_posters, c, s);
    MRPT_SAVE_CONFIG_VAR(clearance_m, c, s);
    MRPT_SAVE_CONFIG_VAR(max_cell_m, c, s);
    MRPT_SAVE_CONFIG_VAR(num_lights, c, s);
    MRPT_SAVE_CONFIG_VAR(light_intensity, c, s);
    MRPT_SAVE_CONFIG_VAR(ambient, c, s);
    MRPT_SAVE_CONFIG_VAR(texture_size_px, c, s);
    MRPT_SAVE_CONFIG_VAR(shadow_map_px, c, s);
}

void WorldOptions::check(const std::string& in) const
{
    core::require(world == "v1" || world == "v2", in + " world", "must be v1 or v2, got '" + world + "'");
    requireRange(gmm_sigma_scale, 0.1, 5, in + " gmm_sigma_scale");
    requireRange(gmm_min_semi_axis_m, 0.001, 1, in + " gmm_min_semi_axis_m");
    requireRange(gmm_max_semi_axis_m, gmm_min_semi_axis_m, 5, in + " gmm_max_semi_axis_m");
    requireRange(shell_margin_m, 0, 1, in + " shell_margin_m");
    for (auto [v, k] : {std::pair{num_boxes, "num_boxes"}, {num_slabs, "num_slabs"}, {num_poles, "num_poles"},
                        {num_wall_posters, "num_wall_posters"}})
        requireRange(v, 0, 200, in + " " + k);
    requireRange(clearance_m, 0, 2, in + " clearance_m");
    requireRange(max_cell_m, 0.05, 5, in + " max_cell_m");
    requireRange(num_lights, 1, 32, in + " num_lights");
    requireRange(light_intensity, 0, 1e4, in + " light_intensity");
    requireRange(ambient, 0, 10, in + " ambient");
    requireRange(texture_size_px, 32, 2048, in + " texture_size_px");
    core::require((texture_size_px & (texture_size_px - 1)) == 0, in + " texture_size_px", "must be a power of two");
    core::require(shadow_map_px == 0 || (shadow_map_px >= 64 && shadow_map_px <= 4096), in + " shadow_map_px",
                  "must be 0 (no shadows) or in [64, 4096]");
}

void AppearanceOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    MRPT_LOAD_CONFIG_VAR(render_scale, double, c, s);
    MRPT_LOAD_CONFIG_VAR(exposure, double, c, s);
    MRPT_LOAD_CONFIG_VAR(exposure_variation, double, c, s);
    MRPT_LOAD_CONFIG_VAR(exposure_period_s, double, c, s);
    MRPT_LOAD_CONFIG_VAR(vignetting, double, c, s);
    MRPT_LOAD_CONFIG_VAR(gamma, double, c, s);
    MRPT_LOAD_CONFIG_VAR(read_noise, double, c, s);
    MRPT_LOAD_CONFIG_VAR(shot_noise, double, c, s);
    MRPT_LOAD_CONFIG_VAR(motion_blur_samples, int, c, s);
    MRPT_LOAD_CONFIG_VAR(exposure_time_ms, double, c, s);
    MRPT_LOAD_CONFIG_VAR(illumination_change, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(illumination_change_start_s, double, c, s);
    MRPT_LOAD_CONFIG_VAR(illumination_change_duration_s, double, c, s);
    MRPT_LOAD_CONFIG_VAR(illumination_change_factor, double, c, s);
    MRPT_LOAD_CONFIG_VAR(auto_exposure_compensation, double, c, s);
    MRPT_LOAD_CONFIG_VAR(auto_exposure_lag_s, double, c, s);
    MRPT_LOAD_CONFIG_VAR(occluder, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(occluder_speed_m_s, double, c, s);
    MRPT_LOAD_CONFIG_VAR(occluder_path_fraction, double, c, s);
}

void AppearanceOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    MRPT_SAVE_CONFIG_VAR(render_scale, c, s);
    MRPT_SAVE_CONFIG_VAR(exposure, c, s);
    MRPT_SAVE_CONFIG_VAR(exposure_variation, c, s);
    MRPT_SAVE_CONFIG_VAR(exposure_period_s, c, s);
    MRPT_SAVE_CONFIG_VAR(vignetting, c, s);
    MRPT_SAVE_CONFIG_VAR(gamma, c, s);
    MRPT_SAVE_CONFIG_VAR(read_noise, c, s);
    MRPT_SAVE_CONFIG_VAR(shot_noise, c, s);
    MRPT_SAVE_CONFIG_VAR(motion_blur_samples, c, s);
    MRPT_SAVE_CONFIG_VAR(exposure_time_ms, c, s);
    MRPT_SAVE_CONFIG_VAR(illumination_change, c, s);
    MRPT_SAVE_CONFIG_VAR(illumination_change_start_s, c, s);
    MRPT_SAVE_CONFIG_VAR(illumination_change_duration_s, c, s);
    MRPT_SAVE_CONFIG_VAR(illumination_change_factor, c, s);
    MRPT_SAVE_CONFIG_VAR(auto_exposure_compensation, c, s);
    MRPT_SAVE_CONFIG_VAR(auto_exposure_lag_s, c, s);
    MRPT_SAVE_CONFIG_VAR(occluder, c, s);
    MRPT_SAVE_CONFIG_VAR(occluder_speed_m_s, c, s);
    MRPT_SAVE_CONFIG_VAR(occluder_path_fraction, c, s);
}

void AppearanceOptions::check(const std::string& in) const
{
    requireRange(render_scale, 0.25, 2, in + " render_scale");
    requireRange(exposure, 1e-3, 1e3, in + " exposure");
    requireRange(exposure_variation, 0, 0.9, in + " exposure_variation");
    requireRange(exposure_period_s, 0.1, 1e4, in + " exposure_period_s");
    requireRange(vignetting, 0, 0.95, in + " vignetting");
    requireRange(gamma, 0.2, 5, in + " gamma");
    requireRange(read_noise, 0, 50, in + " read_noise");
    requireRange(shot_noise, 0, 10, in + " shot_noise");
    requireRange(motion_blur_samples, 1, 16, in + " motion_blur_samples");
    requireRange(exposure_time_ms, 0, 50, in + " exposure_time_ms");
    requireRange(illumination_change_start_s, 0, 1e5, in + " illumination_change_start_s");
    requireRange(illumination_change_duration_s, 2, 1e5, in + " illumination_change_duration_s");
    requireRange(illumination_change_factor, 0, 1, in + " illumination_change_factor");
    requireRange(auto_exposure_compensation, 0, 1, in + " auto_exposure_compensation");
    requireRange(auto_exposure_lag_s, 0, 10, in + " auto_exposure_lag_s");
    requireRange(occluder_speed_m_s, 0, 5, in + " occluder_speed_m_s");
    requireRange(occluder_path_fraction, 0.05, 0.5, in + " occluder_path_fraction");
}

void LidarOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    MRPT_LOAD_CONFIG_VAR(density_per_m2, double, c, s);
    MRPT_LOAD_CONFIG_VAR(range_noise_mm, double, c, s);
    MRPT_LOAD_CONFIG_VAR(num_stations, int, c, s);
    MRPT_LOAD_CONFIG_VAR(station_height_m, double, c, s);
    MRPT_LOAD_CONFIG_VAR(visibility_from_stations, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(cubemap_size_px, int, c, s);
    MRPT_LOAD_CONFIG_VAR(reflectivity_noise, double, c, s);
    MRPT_LOAD_CONFIG_VAR(incidence_weight, double, c, s);
    MRPT_LOAD_CONFIG_VAR(range_falloff_m, double, c, s);
    MRPT_LOAD_CONFIG_VAR(beam_map, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(beam_num_scans, int, c, s);
    MRPT_LOAD_CONFIG_VAR(beam_azimuth_steps, int, c, s);
    MRPT_LOAD_CONFIG_VAR(beam_min_elevation_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(beam_max_elevation_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(beam_range_noise_mm, double, c, s);
}

void LidarOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    MRPT_SAVE_CONFIG_VAR(density_per_m2, c, s);
    MRPT_SAVE_CONFIG_VAR(range_noise_mm, c, s);
    MRPT_SAVE_CONFIG_VAR(num_stations, c, s);
    MRPT_SAVE_CONFIG_VAR(station_height_m, c, s);
    MRPT_SAVE_CONFIG_VAR(visibility_from_stations, c, s);
    MRPT_SAVE_CONFIG_VAR(cubemap_size_px, c, s);
    MRPT_SAVE_CONFIG_VAR(reflectivity_noise, c, s);
    MRPT_SAVE_CONFIG_VAR(incidence_weight, c, s);
    MRPT_SAVE_CONFIG_VAR(range_falloff_m, c, s);
    MRPT_SAVE_CONFIG_VAR(beam_map, c, s);
    MRPT_SAVE_CONFIG_VAR(beam_num_scans, c, s);
    MRPT_SAVE_CONFIG_VAR(beam_azimuth_steps, c, s);
    MRPT_SAVE_CONFIG_VAR(beam_min_elevation_deg, c, s);
    MRPT_SAVE_CONFIG_VAR(beam_max_elevation_deg, c, s);
    MRPT_SAVE_CONFIG_VAR(beam_range_noise_mm, c, s);
}

void LidarOptions::check(const std::string& in) const
{
    requireRange(density_per_m2, 1, 1e6, in + " density_per_m2");
    requireRange(range_noise_mm, 0, 1000, in + " range_noise_mm");
    requireRange(num_stations, 1, 64, in + " num_stations");
    requireRange(station_height_m, 0.1, 3, in + " station_height_m");
    requireRange(cubemap_size_px, 64, 4096, in + " cubemap_size_px");
    requireRange(reflectivity_noise, 0, 1, in + " reflectivity_noise");
    requireRange(incidence_weight, 0, 1, in + " incidence_weight");
    requireRange(range_falloff_m, 0.1, 1e4, in + " range_falloff_m");
    requireRange(beam_num_scans, 1, 1000, in + " beam_num_scans");
    requireRange(beam_azimuth_steps, 16, 100000, in + " beam_azimuth_steps");
    requireRange(beam_min_elevation_deg, -89, 89, in + " beam_min_elevation_deg");
    requireRange(beam_max_elevation_deg, beam_min_elevation_deg, 89, in + " beam_max_elevation_deg");
    requireRange(beam_range_noise_mm, 0, 1000, in + " beam_range_noise_mm");
}

}  // namespace quasiloc::sim
