#pragma once
// The prior LiDAR map of the simulated world, as a terrestrial survey scanner would produce it.
//
// Dense ("survey") map, decisions:
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
#include <Eigen/Core>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/sim/world.h>
#include <vector>

namespace quasiloc::sim
{
/** Section [Lidar]; each key's unit, range and meaning: declare() (sim_options.cpp). */
struct LidarOptions : public core::DeclaredOptions
{
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

    void declare(core::OptionTable& t) override;
    /** The declared ranges, then beam_max_elevation_deg >= beam_min_elevation_deg (InputError naming `input`). */
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
