// The keys of the sim library's option structs, each declared once (name, member, unit, range, meaning), and the
// checks that a range cannot say.
#include <quasiloc/core/error.h>
#include <quasiloc/sim/lidar_sampler.h>
#include <quasiloc/sim/stereo_renderer.h>
#include <quasiloc/sim/world_builder.h>

namespace quasiloc::sim
{
using core::Range;

void WorldOptions::declare(core::OptionTable& t)
{
    t.addEnum("world", world,
              {{"v1", ViconRoom::v1},
               {"v2", ViconRoom::v2},
               {"floor", ViconRoom::office_floor},
               {"campus", ViconRoom::campus}},
              "the EuRoC Vicon room (1 or 2): shell and clutter from its GMM and line maps; floor: the ground "
              "robot's office floor of rooms along a corridor (floor_world.h, keys floor_*); campus: outdoor streets "
              "and blocks of buildings (campus_world.h, keys campus_*; needs [Simulation] motion = car)");
    t.add("gmm_patches", gmm_patches, "interior GMM components as elliptical patches");
    t.add("gmm_sigma_scale", gmm_sigma_scale, "", Range::between(0.1, 5), "patch semi-axis = scale * sigma");
    t.add("gmm_min_semi_axis_m", gmm_min_semi_axis_m, "m", Range::between(0.001, 1),
          "smaller components are skipped (noise-sized)");
    t.add("gmm_max_semi_axis_m", gmm_max_semi_axis_m, "m", Range::between(0.001, 5),
          "larger patch semi-axes are cut to this (>= gmm_min_semi_axis_m)");
    t.add("shell_margin_m", shell_margin_m, "m", Range::between(0, 1),
          "components closer than this to the shell belong to it");
    t.add("num_boxes", num_boxes, "", Range::between(0, 200), "cardboard boxes, sometimes stacked two high");
    t.add("num_slabs", num_slabs, "", Range::between(0, 200), "mattresses lying flat or leaning against something");
    t.add("num_poles", num_poles, "", Range::between(0, 200), "floor-to-ceiling poles with reflective tape");
    t.add("num_wall_posters", num_wall_posters, "", Range::between(0, 200),
          "posters and calibration boards 1 cm off a wall");
    t.add("clearance_m", clearance_m, "m", Range::between(0, 2),
          "every triangle keeps this far from the room's ground-truth trajectories (patches shrink, objects move)");
    t.add("max_cell_m", max_cell_m, "m", Range::between(0.05, 5), "triangle size (lighting resolution)");
    t.add("num_lights", num_lights, "", Range::between(1, 32), "point lights below the ceiling, in one or two rows");
    t.add("light_intensity", light_intensity, "", Range::between(0, 1e4), "intensity of each light");
    t.add("ambient", ambient, "", Range::between(0, 10), "irradiance without any light");
    t.add("texture_size_px", texture_size_px, "px", Range::between(32, 2048),
          "side of the procedural albedo textures (a power of two)");
    t.addEnum("materials", materials, {{"procedural", MaterialSet::procedural}, {"spectral", MaterialSet::spectral}},
              "procedural: albedo and LiDAR reflectivity share a structure layer by design; spectral: visible albedo "
              "and ~905 nm reflectance of real surfaces, each with its own texture (spectral_materials.h, "
              "docs/crossmodal_statistics.md)");
    t.add("shadow_map_px", shadow_map_px, "px", Range::between(0, 4096),
          "cube-map size for light shadows; 0 = no shadows, else >= 64");
    t.add("floor_corridor_length_m", floor.corridor_length_m, "m", Range::between(2, 500),
          "world = floor: length of the corridor (the rooms on each side partition it)");
    t.add("floor_corridor_width_m", floor.corridor_width_m, "m", Range::between(1.2, 10), "world = floor");
    t.add("floor_room_depth_m", floor.room_depth_m, "m", Range::between(2.5, 30),
          "world = floor: rooms' extent away from the corridor");
    t.add("floor_room_width_m", floor.room_width_m, "m", Range::between(2.5, 50),
          "world = floor: mean room width along the corridor (each drawn in [0.75, 1.25] x this)");
    t.add("floor_ceiling_m", floor.ceiling_m, "m", Range::between(2.2, 10), "world = floor: ceiling height");
    t.add("floor_door_width_m", floor.door_width_m, "m", Range::between(0.8, 5), "world = floor: one door per room");
    t.add("floor_furniture_per_room", floor.furniture_per_room, "", Range::between(0, 50),
          "world = floor: tables, shelves and box stacks against a room's walls");
    t.add("floor_posters_per_room", floor.posters_per_room, "", Range::between(0, 50), "world = floor");
    t.add("floor_corridor_posters", floor.corridor_posters, "", Range::between(0, 100),
          "world = floor: posters on the corridor's otherwise plain walls");
    t.add("campus_block_size_m", campus.block_size_m, "m", Range::between(30, 500),
          "world = campus: street centreline spacing (a block and a street); the campus spans "
          "(campus_blocks_per_side x this)^2 between its outer streets (10 x 100 m = 1 km^2)");
    t.add("campus_blocks_per_side", campus.blocks_per_side, "", Range::between(1, 50), "world = campus");
    t.add("campus_street_width_m", campus.street_width_m, "m", Range::between(6, 40),
          "world = campus: carriageway kerb to kerb (two driving lanes and a parking strip each side)");
    t.add("campus_sidewalk_width_m", campus.sidewalk_width_m, "m", Range::between(1.5, 10), "world = campus");
    t.add("campus_building_min_height_m", campus.building_min_height_m, "m", Range::between(3, 200),
          "world = campus: lowest building");
    t.add("campus_building_max_height_m", campus.building_max_height_m, "m", Range::between(3, 200),
          "world = campus: highest building (>= campus_building_min_height_m)");
    t.add("campus_storey_m", campus.storey_m, "m", Range::between(2.5, 6),
          "world = campus: one row of windows per storey");
    t.add("campus_trees_per_side", campus.trees_per_side, "", Range::between(0, 50),
          "world = campus: trees on the sidewalk of each side of a block");
    t.add("campus_parked_cars_per_side", campus.parked_cars_per_side, "", Range::between(0, 50),
          "world = campus: cars parked along each side of a block");
    t.add("campus_people_per_side", campus.people_per_side, "", Range::between(0, 50),
          "world = campus: people standing on the sidewalk of each side of a block");
    t.add("campus_margin_m", campus.margin_m, "m", Range::between(1, 200),
          "world = campus: pavement beyond the outer streets, up to the boundary wall");
}

void WorldOptions::check(const std::string& in) const
{
    checkRanges(in);
    core::require(gmm_max_semi_axis_m >= gmm_min_semi_axis_m, in + " gmm_max_semi_axis_m",
                  "must be >= gmm_min_semi_axis_m");
    core::require((texture_size_px & (texture_size_px - 1)) == 0, in + " texture_size_px", "must be a power of two");
    core::require(shadow_map_px == 0 || shadow_map_px >= 64, in + " shadow_map_px",
                  "must be 0 (no shadows) or in [64, 4096]");
}

void AppearanceOptions::declare(core::OptionTable& t)
{
    t.add("render_scale", render_scale, "", Range::between(0.25, 2),
          "focal length of the internal pinhole relative to the camera's");
    t.add("exposure", exposure, "", Range::between(1e-3, 1e3), "linear gain from radiance to sensor signal [0,1]");
    t.add("exposure_variation", exposure_variation, "", Range::between(0, 0.9),
          "relative amplitude of the slow (sine) exposure drift");
    t.add("exposure_period_s", exposure_period_s, "s", Range::between(0.1, 1e4), "period of the exposure drift");
    t.add("vignetting", vignetting, "", Range::between(0, 0.95), "relative darkening in the image corners");
    t.add("gamma", gamma, "", Range::between(0.2, 5), "sensor gamma before 8-bit quantisation");
    t.add("read_noise", read_noise, "", Range::between(0, 50), "std of the read noise in 8-bit units");
    t.add("shot_noise", shot_noise, "", Range::between(0, 10),
          "shot noise std in 8-bit units at full scale is shot_noise*sqrt(255)");
    t.add("motion_blur_samples", motion_blur_samples, "", Range::between(1, 16),
          "poses averaged across the exposure time; 1 = no blur");
    t.add("exposure_time_ms", exposure_time_ms, "ms", Range::between(0, 50), "spread of the blur samples");
    t.add("illumination_change", illumination_change,
          "an episode where the lights dim and every other light turns off");
    t.add("illumination_change_start_s", illumination_change_start_s, "s", Range::between(0, 1e5),
          "start of the episode, since the start of the trajectory");
    t.add("illumination_change_duration_s", illumination_change_duration_s, "s", Range::between(2, 1e5),
          "length of the episode");
    t.add("illumination_change_factor", illumination_change_factor, "", Range::between(0, 1),
          "intensity of the lights that stay on");
    t.add("auto_exposure_compensation", auto_exposure_compensation, "", Range::between(0, 1),
          "exponent of the auto-exposure's answer to the dimming: 0 = none, 1 = full compensation");
    t.add("auto_exposure_lag_s", auto_exposure_lag_s, "s", Range::between(0, 10),
          "delay of the auto-exposure behind the lights");
    t.add("occluder", occluder, "a person-sized box walking an ellipse in the room");
    t.add("occluder_speed_m_s", occluder_speed_m_s, "m/s", Range::between(0, 5), "walking speed of the occluder");
    t.add("occluder_path_fraction", occluder_path_fraction, "", Range::between(0.05, 0.5),
          "ellipse semi-axes as fraction of the room extent");
    t.add("auto_exposure_step", auto_exposure_step, "", Range::between(0, 1),
          "0: the exposure follows its drift continuously; > 0: an auto-exposure that steps: the exposure moves in "
          "discrete relative steps of this size, updated every auto_exposure_interval_s");
    t.add("auto_exposure_interval_s", auto_exposure_interval_s, "s", Range::between(0.01, 100),
          "auto_exposure_step > 0: how often the auto-exposure may change the exposure");
}

void AppearanceOptions::check(const std::string& in) const { checkRanges(in); }

void LidarOptions::declare(core::OptionTable& t)
{
    t.addEnum("map_source", map_source, {{"exact", MapSource::exact}, {"sweeps", MapSource::sweeps}},
              "exact: points sampled on the true surfaces from survey stations (the keys below up to beam_*); "
              "sweeps: the map a user builds: simulated LiDAR sweeps of a mapping run (keys sweep_*, rosette_*) "
              "fused by map-build with carving and ring/range normalisation (lidar_sweeps.h, docs/sim-rawlog.md)");
    t.add("density_per_m2", density_per_m2, "1/m^2", Range::between(1, 1e6), "points sampled per square metre");
    t.add("range_noise_mm", range_noise_mm, "mm", Range::between(0, 1000),
          "survey-grade range noise along the ray from the station that sees the point");
    t.add("num_stations", num_stations, "", Range::between(1, 64), "scanner stations (farthest-point sampling)");
    t.add("station_height_m", station_height_m, "m", Range::between(0.1, 3), "height of the stations");
    t.add("visibility_from_stations", visibility_from_stations, "keep only points some station sees (scan shadows)");
    t.add("cubemap_size_px", cubemap_size_px, "px", Range::between(64, 4096),
          "side of a station's visibility cube map");
    t.add("reflectivity_noise", reflectivity_noise, "", Range::between(0, 1), "std of the reflectivity noise");
    t.add("incidence_weight", incidence_weight, "", Range::between(0, 1),
          "reflectivity x (1 - w + w * cos(incidence))");
    t.add("range_falloff_m", range_falloff_m, "m", Range::between(0.1, 1e4),
          "reflectivity x 1 / (1 + (range / range_falloff_m)^2)");
    t.add("beam_map", beam_map, "also produce the sparse 32-beam-like map");
    t.add("beam_num_scans", beam_num_scans, "", Range::between(1, 1000), "32-beam map: scan stations");
    t.add("beam_azimuth_steps", beam_azimuth_steps, "", Range::between(16, 100000), "32-beam map: beams per turn");
    t.add("beam_min_elevation_deg", beam_min_elevation_deg, "deg", Range::between(-89, 89), "32-beam map: lowest beam");
    t.add("beam_max_elevation_deg", beam_max_elevation_deg, "deg", Range::between(-89, 89),
          "32-beam map: highest beam (>= beam_min_elevation_deg)");
    t.add("beam_range_noise_mm", beam_range_noise_mm, "mm", Range::between(0, 1000),
          "32-beam map: the beam sensor's range noise");
    addSweepKeys(t);
}

void LidarOptions::addSweepKeys(core::OptionTable& t)
{
    t.addEnum("sweep_pattern", sweep_pattern,
              {{"spinning", SweepPattern::spinning}, {"rosette", SweepPattern::rosette}},
              "sweeps: spinning multi-beam LiDAR (sweep_beams rings), or a Livox-like forward-looking "
              "non-repetitive rosette (two counter-rotating prisms, one emitter)");
    t.add("sweep_beams", sweep_beams, "", Range::between(1, 128), "spinning: beams (rings), e.g. 32 or 64");
    t.add("sweep_azimuth_steps", sweep_azimuth_steps, "", Range::between(16, 100000),
          "spinning: firings per beam and turn (1800 = 0.2 deg)");
    t.add("sweep_min_elevation_deg", sweep_min_elevation_deg, "deg", Range::between(-89, 89),
          "spinning: lowest beam (beams evenly spread up to sweep_max_elevation_deg)");
    t.add("sweep_max_elevation_deg", sweep_max_elevation_deg, "deg", Range::between(-89, 89),
          "spinning: highest beam (>= sweep_min_elevation_deg)");
    t.add("sweep_tilt_deg", sweep_tilt_deg, "deg", Range::between(-90, 90),
          "mount pitch of the mapping LiDAR (a handheld mapper's tilt, so that the ceiling and floor are swept)");
    t.add("sweep_rate_hz", sweep_rate_hz, "Hz", Range::between(1, 50), "sweeps (frames) per second");
    t.add("sweep_every", sweep_every, "", Range::between(1, 100),
          "every N-th sweep of the run goes to map-build (as KITTI's velodyne_even), to bound generation time");
    t.add("rosette_points_per_s", rosette_points_per_s, "1/s", Range::between(1000, 2e6), "rosette: point rate");
    t.add("rosette_fov_deg", rosette_fov_deg, "deg", Range::between(5, 120), "rosette: circular field of view");
    t.add("sweep_speed_m_s", sweep_speed_m_s, "m/s", Range::between(0.05, 5), "walking speed of the mapping run");
    t.add("sweep_min_height_m", sweep_min_height_m, "m", Range::between(0.2, 3),
          "the mapping LiDAR's height above the floor varies between this and sweep_max_height_m");
    t.add("sweep_max_height_m", sweep_max_height_m, "m", Range::between(0.2, 3), "(>= sweep_min_height_m)");
    t.add("sweep_range_noise_mm", sweep_range_noise_mm, "mm", Range::between(0, 1000),
          "std of the range noise of a return");
    t.add("sweep_divergence_mrad", sweep_divergence_mrad, "mrad", Range::between(0, 50),
          "full beam divergence: a footprint straddling a depth edge returns a mixed range");
    t.add("sweep_mixed_max_gap_m", sweep_mixed_max_gap_m, "m", Range::between(0, 100),
          "footprint depths further apart than this give the nearer return, not a mixed one");
    t.add("sweep_ring_gain_error", sweep_ring_gain_error, "", Range::between(0, 1),
          "std of the log of each ring's intensity gain (per-ring calibration error)");
    t.add("sweep_glass_panes", sweep_glass_panes, "", Range::between(0, 50),
          "window panes in the outer walls that return nothing to the LiDAR (the camera sees the wall as before)");
    t.add("sweep_people", sweep_people, "", Range::between(0, 50),
          "people walking back and forth while mapping (absent from the camera sequence)");
    t.add("sweep_furniture", sweep_furniture, "", Range::between(0, 50),
          "chairs, tables and cabinets present while mapping (half of them moved half-way through the run), gone "
          "when the camera sequence runs");
    t.add("sweep_drift_m", sweep_drift_m, "m", Range::between(0, 1),
          "largest position error of the mapping poses handed to map-build (LiDAR-inertial drift, pulled back at "
          "loop closures)");
    t.add("sweep_drift_deg", sweep_drift_deg, "deg", Range::between(0, 10),
          "largest orientation error of the mapping poses");
    t.add("sweep_voxel_m", sweep_voxel_m, "m", Range::between(0.005, 1), "map-build voxel_size_m");
    t.add("sweep_min_range_m", sweep_min_range_m, "m", Range::between(0, 100), "map-build min_range_m");
    t.add("sweep_cubemap_px", sweep_cubemap_px, "px", Range::between(64, 4096),
          "side of the per-sweep cube map the beams are cast through (1024: 0.09 deg at a face's centre)");
}

void LidarOptions::check(const std::string& in) const
{
    checkRanges(in);
    core::require(beam_max_elevation_deg >= beam_min_elevation_deg, in + " beam_max_elevation_deg",
                  "must be >= beam_min_elevation_deg");
    core::require(sweep_max_elevation_deg >= sweep_min_elevation_deg, in + " sweep_max_elevation_deg",
                  "must be >= sweep_min_elevation_deg");
    core::require(sweep_max_height_m >= sweep_min_height_m, in + " sweep_max_height_m",
                  "must be >= sweep_min_height_m");
}

}  // namespace quasiloc::sim
