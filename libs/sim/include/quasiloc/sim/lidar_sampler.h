#pragma once
// The prior LiDAR map of the simulated world: by default the map a user builds from a mobile LiDAR's sweeps
// (map_source = sweeps, lidar_sweeps.h); for controlled experiments the exact map a terrestrial survey scanner would
// produce (map_source = exact).
//
// Exact ("survey") map, decisions:
//  - points are sampled uniformly on every triangle at density_per_m2 (deterministic per triangle and seed,
//    independent of threading);
//  - scanner stations: num_stations positions at station_height_m, chosen by farthest-point sampling among
//    grid candidates at least 0.5 m from any geometry; a point is kept only if some station sees it
//    (cube-map z-buffer of the station, rasterizer.h), so objects cast scan shadows as in a real survey;
//  - geometry noise: survey-grade range noise (range_noise_mm, along the ray from the station that sees it);
//  - reflectivity = intrinsic material reflectivity (materials.h: NOT the camera albedo) x incidence falloff
//    (1 - incidence_weight + incidence_weight * cos) x range falloff 1 / (1 + (r / range_falloff_m)^2)
//    + Gaussian noise, clamped to [0, 1].
// Sparse variant ("32-beam"): scans of a 32-beam spinning LiDAR (elevations evenly spread over
// [beam_min_elevation_deg, beam_max_elevation_deg], beam_azimuth_steps per turn) from beam_num_scans
// stations, cast through the same cube maps, with the beam sensor's own (cm-level) range noise.
// Swept map (map_source = sweeps, keys sweep_*): simulated sweeps of a mapping run through map-build
// (lidar_sweeps.h).
#include <Eigen/Core>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/sim/world.h>
#include <vector>

namespace quasiloc::sim
{
/** Where the sequence's lidar_map.map comes from: the exact survey sampler, or map-build over simulated sweeps. */
enum class MapSource
{
    exact,
    sweeps
};

/** The mapping LiDAR's scan pattern: a spinning multi-beam LiDAR, or a Livox-like non-repetitive rosette. */
enum class SweepPattern
{
    spinning,
    rosette
};

/** Section [Lidar]; each key's unit, range and meaning: declare() (sim_options.cpp). */
struct LidarOptions : public core::DeclaredOptions
{
    MapSource map_source = MapSource::sweeps;
    double density_per_m2 = 6000;
    double range_noise_mm = 2.0;
    int num_stations = 5;
    double station_height_m = 1.5;
    bool visibility_from_stations = true;
    int cubemap_size_px = 1024;
    double reflectivity_noise = 0.02;
    double incidence_weight = 0.5;
    double range_falloff_m = 12.0;
    bool beam_map = false;
    int beam_num_scans = 6;
    int beam_azimuth_steps = 1800;
    double beam_min_elevation_deg = -30.67;
    double beam_max_elevation_deg = 10.67;
    double beam_range_noise_mm = 20.0;
    SweepPattern sweep_pattern = SweepPattern::spinning;
    /** A 64-beam LiDAR with a 90 deg vertical field (as the Ouster OS0-64 that building mappers carry): a 32-beam
     *  -25..15 deg one maps 39 % of a room's ceiling, and the global start needs it (docs/benchmarks.md). */
    int sweep_beams = 64;
    int sweep_azimuth_steps = 1800;
    double sweep_min_elevation_deg = -45.0;
    double sweep_max_elevation_deg = 45.0;
    double sweep_tilt_deg = 0.0;
    double sweep_rate_hz = 10.0;
    int sweep_every = 4;
    double rosette_points_per_s = 100000;
    double rosette_fov_deg = 70.0;
    double sweep_speed_m_s = 0.5;
    double sweep_min_height_m = 1.0;
    double sweep_max_height_m = 1.8;
    double sweep_range_noise_mm = 25.0;
    double sweep_divergence_mrad = 3.0;
    double sweep_mixed_max_gap_m = 0.5;
    double sweep_ring_gain_error = 0.1;
    int sweep_glass_panes = 2;
    int sweep_people = 2;
    int sweep_furniture = 4;
    double sweep_drift_m = 0.02;
    double sweep_drift_deg = 0.2;
    double sweep_voxel_m = 0.03;
    double sweep_min_range_m = 0.5;
    int sweep_cubemap_px = 1024;

    void declare(core::OptionTable& t) override;
    /** The sweep_* and rosette_* keys (map_source = sweeps). */
    void addSweepKeys(core::OptionTable& t);
    /** The declared ranges, then beam_max_elevation_deg >= beam_min_elevation_deg, the same for sweep_*, and
     *  sweep_max_height_m >= sweep_min_height_m (InputError naming `input`). */
    void check(const std::string& input) const;
};

struct LidarStats
{
    size_t sampled = 0;      ///< points sampled on surfaces
    size_t kept = 0;         ///< points in the map
    size_t not_visible = 0;  ///< dropped: no station sees them
    std::vector<Eigen::Vector3f> stations;
};

/** Per-point extras for tests and statistics (same order as the map). */
struct LidarPointInfo
{
    std::vector<float> albedo;  ///< camera albedo (level 0) at the point
    std::vector<uint16_t> material;
};

/** Scanner station positions (farthest-point sampling, see above). */
std::vector<Eigen::Vector3f> chooseStations(const World& world, int count, double height_m);

map::LidarMap sampleSurveyMap(const World& world, const LidarOptions& options, uint64_t seed,
                              LidarStats* stats = nullptr, LidarPointInfo* info = nullptr);

map::LidarMap sampleBeamMap(const World& world, const LidarOptions& options, uint64_t seed,
                            LidarStats* stats = nullptr);

}  // namespace quasiloc::sim
