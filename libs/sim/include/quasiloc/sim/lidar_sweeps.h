#pragma once
// The map a user builds: simulated LiDAR sweeps of a mapping run through the world, fused by map-build
// (map::buildMap, the same code and options a user's scans go through) into the sequence's lidar_map.map.
//
// Model ([Lidar] keys sweep_*, rosette_*; docs/sim-rawlog.md):
//  - mapping run: a walk through the world's free space at sweep_speed_m_s, the LiDAR between sweep_min_height_m and
//    sweep_max_height_m, pitched by sweep_tilt_deg, its yaw following the walk. EuRoC rooms: two loops around and
//    through the room (the loop scale with the most clearance of a few candidates); the office floor: a tour of the
//    rooms and the corridor given as waypoints (robot_motion.h planFloorTour);
//  - sweeps at sweep_rate_hz with per-point times (a spinning LiDAR fires column by column over the turn; the
//    rosette point by point); every sweep_every-th goes to map-build;
//  - ray casting: one cube map per sweep (rasterizer.h, one thread) rendered at the LiDAR's position mid-sweep,
//    with the people and furniture of that instant; a beam's hit is the exact intersection with the triangle the
//    cube map shows, expressed in the LiDAR frame of the beam's own time (so the sweep is skewed by the motion as a
//    real one is, and map-build deskews it);
//  - beam divergence: five rays over the footprint; where they are not one plane (opposite rays do not average to the
//    centre's range within 2 cm, or some hit nothing) their depths give a mixed range (their mean) when they lie
//    within sweep_mixed_max_gap_m, else the nearest;
//  - range noise sweep_range_noise_mm along the beam; returns on glass (sweep_glass_panes windows in the outer walls,
//    and every triangle of material kGlass: the campus's windows and car cabins): none;
//  - intensity = 255 x (material's intrinsic NIR reflectivity x incidence x range fall-off (incidence_weight,
//    range_falloff_m as for the exact map) x the ring's gain (log-normal, sweep_ring_gain_error) + noise),
//    quantised to 8 bits like a real sensor's;
//  - people (kPersonClothes cylinders) walk back and forth while mapping; furniture stands in the room while mapping
//    (half of it moved half-way through); neither exists when the camera sequence runs;
//  - the poses handed to map-build carry a LiDAR-inertial odometry's error: a random walk in position and
//    orientation, pulled to zero at loop closures (the run passing again within 1 m of a place 20 s or more
//    earlier: a Brownian bridge between closures), scaled so that its largest value over the run is sweep_drift_m
//    and sweep_drift_deg.
#include <Eigen/Geometry>
#include <quasiloc/map/map_build.h>
#include <quasiloc/sim/lidar_sampler.h>
#include <quasiloc/sim/world.h>
#include <string>
#include <vector>

namespace quasiloc::sim
{
/** The mapping run: true and estimated LiDAR poses at 100 Hz. */
struct MappingRun
{
    std::vector<double> t;                             ///< seconds from the run's start
    std::vector<Eigen::Isometry3d> T_world_lidar;      ///< true
    std::vector<Eigen::Isometry3d> T_world_lidar_est;  ///< as a LiDAR-inertial odometry with loop closures leaves it
    std::vector<double> loop_closure_t;                ///< when the drift is pulled back
    double length_m = 0;

    double duration() const { return t.empty() ? 0 : t.back(); }
    /** Interpolated (linear, slerp) true or estimated pose at time s (clamped to the run). */
    Eigen::Isometry3d pose(double s, bool estimated = false) const;
};

/** Plans the run along `waypoints` (positions; z is replaced by the height profile), then draws its drift. An empty
 *  `waypoints` plans the two loops of a EuRoC room inside world.room. */
MappingRun planMappingRun(const World& world, const std::vector<Eigen::Vector3f>& waypoints, const LidarOptions& o,
                          uint64_t seed);

/** The largest position [m] and orientation [deg] error of the estimated poses over the run. */
std::pair<double, double> mappingRunDrift(const MappingRun& run);

struct Person
{
    Eigen::Vector2f a, b;  ///< walks a -> b -> a ...
    float speed_m_s = 1.2f, phase_s = 0, radius_m = 0.22f, height_m = 1.75f;
    Eigen::Vector2f at(double t) const;
};

struct MovedFurniture
{
    Eigen::Vector3f size;  ///< full sizes x y z
    Eigen::Vector3f centre_before, centre_after;
    float yaw_before = 0, yaw_after = 0;
    bool moved = false;  ///< at centre_after from half the run on; otherwise at centre_before all along
    uint16_t material = 0;
};

struct GlassPane
{
    Eigen::Vector3f origin, u, v;  ///< origin + s u + t v, s, t in [0, 1], on an outer wall
    Eigen::Vector3f normal;
    /** Is p on the pane (within 3 cm of its plane)? */
    bool contains(const Eigen::Vector3f& p) const;
};

/** What is in the world only while mapping, and the glass. */
struct MappingScene
{
    std::vector<Person> people;
    std::vector<MovedFurniture> furniture;
    std::vector<GlassPane> glass;
    double run_duration_s = 0;
    float floor_z = 0;

    /** The people and furniture at run time t, as one mesh. */
    Mesh meshAt(double t) const;
    bool onGlass(const Eigen::Vector3f& p) const;
};

/** People and furniture in free space (clear of the geometry and, furniture, of the run), panes on the outer walls. */
MappingScene makeMappingScene(const World& world, const MappingRun& run, const LidarOptions& o, uint64_t seed);

struct SweepStats
{
    size_t sweeps_run = 0, sweeps_used = 0;
    size_t rays = 0, returns = 0, no_return = 0, glass_dropped = 0, mixed = 0, transient_returns = 0;
};

/** The sweeps handed to map-build, in memory (a map::ScanSource). */
class SimulatedSweeps : public map::ScanSource
{
   public:
    std::string name(size_t i) const override { return scans[i].name; }
    map::LidarScan read(size_t i) const override { return scans[i]; }
    size_t size() const override { return scans.size(); }

    std::vector<map::LidarScan> scans;  ///< points in the LiDAR frame, time_s after the stamp, 8-bit intensities
    std::vector<double> stamps;         ///< each sweep's start, seconds of the run
};

/** Simulates the used sweeps of the run (deterministic for a seed). */
SimulatedSweeps simulateSweeps(const World& world, const MappingScene& scene, const MappingRun& run,
                               const LidarOptions& o, uint64_t seed, SweepStats* stats = nullptr);

/** The run's estimated trajectory as map-build's ScanPoses (T_body_lidar = identity). */
map::ScanPoses mappingPoses(const MappingRun& run, const SimulatedSweeps& sweeps);

/** map-build's options for the swept map: its defaults (carving, ring and range normalisation) with the voxel and
 *  the minimum range of the [Lidar] keys, as a user mapping a room would set them. */
map::MapBuildOptions sweptMapBuildOptions(const LidarOptions& o, const std::string& output_name);

/** How close a map is to the world's true surfaces. */
struct SweptMapQuality
{
    size_t points = 0;
    double median_error_m = 0, p95_error_m = 0;  ///< distance to the camera world's surfaces (capped at 0.2 m)
    double share_beyond_10cm = 0;
    double coverage = 0;  ///< share of surface samples (walls, floor, ceiling, objects) with a map point within 5 cm
    double coverage_by_part[4] = {0, 0, 0, 0};  ///< the same for the floor, the ceiling, the outer walls, the rest
    size_t person_points_fused = 0, person_points_removed = 0;  ///< fused voxels on people, removed by carving
    size_t furniture_points_fused = 0, furniture_points_removed = 0;
    size_t glass_points = 0;  ///< map points on the glass panes
};

/** `removed`: the points the carving removed (may be empty). Surfaces are those of `world` (the camera's). */
SweptMapQuality evaluateSweptMap(const World& world, const MappingScene& scene, const map::LidarMap& map,
                                 const map::LidarMap& removed);

struct SweptMap
{
    MappingRun run;
    MappingScene scene;
    SweepStats sweeps;
    map::MapBuildResult build;
    SweptMapQuality quality;
    double simulate_s = 0, build_s = 0, evaluate_s = 0;
    std::string summary() const;
};

/** Everything above: run, scene, sweeps, map-build, quality. */
SweptMap buildSweptMap(const World& world, const std::vector<Eigen::Vector3f>& waypoints, const LidarOptions& o,
                       uint64_t seed, const std::string& output_name);

}  // namespace quasiloc::sim
