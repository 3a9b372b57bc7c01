// Simulated LiDAR sweeps of the mapping run and the swept map built from them (lidar_sweeps.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <quasiloc/core/pose.h>
#include <quasiloc/sim/lidar_sweeps.h>
#include <quasiloc/sim/rasterizer.h>
#include <random>
#include <sstream>

namespace quasiloc::sim
{
namespace
{
double secondsSince(std::chrono::steady_clock::time_point a)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
}

struct Hit
{
    float range = 0;         ///< from the cube's centre
    float reflectivity = 0;  ///< intrinsic x incidence (range fall-off and gain come later)
    bool glass = false, moving = false;
};

/** Casts one sweep's rays through its cube map. */
class SweepCaster
{
   public:
    SweepCaster(const World& world, const Mesh& moving, const MappingScene& scene, const CubeMap& cube,
                const LidarOptions& o)
        : world_(world), moving_(moving), scene_(scene), cube_(cube), o_(o)
    {}

    /** The ray along unit d from the cube's centre; false: nothing there. */
    bool cast(const Eigen::Vector3f& d, Hit& hit) const
    {
        float z_face;
        const VisibilitySample* px = cube_.lookup(d, z_face);
        if (px->tri < 0 || z_face <= 0) return false;
        const auto n_static = int32_t(world_.mesh.triangles.size());
        hit.moving = px->tri >= n_static;
        const Mesh& mesh = hit.moving ? moving_ : world_.mesh;
        const Triangle& tri = mesh.triangles[size_t(hit.moving ? px->tri - n_static : px->tri)];
        const Eigen::Vector3f a = mesh.vertices[tri.v[0]].p, b = mesh.vertices[tri.v[1]].p,
                              c = mesh.vertices[tri.v[2]].p;
        Eigen::Vector3f normal = (b - a).cross(c - a);
        normal /= std::max(normal.norm(), 1e-12f);
        // The exact intersection with the triangle's plane (the pixel's depth is its centre's, not the beam's).
        float range = px->depth / z_face;
        const float denom = normal.dot(d);
        if (std::abs(denom) > 0.02f)
        {
            const float t = normal.dot(a - cube_.centre) / denom;
            if (t > 0 && std::abs(t - range) < 0.05f + 0.05f * range) range = t;
        }
        hit.range = range;
        const Eigen::Vector3f p = cube_.centre + range * d;
        hit.glass = !hit.moving && (tri.material == kGlass || scene_.onGlass(p));
        const float b1 = px->b1, b2 = px->b2;
        const Eigen::Vector2f uv = (1 - b1 - b2) * mesh.vertices[tri.v[0]].uv + b1 * mesh.vertices[tri.v[1]].uv +
                                   b2 * mesh.vertices[tri.v[2]].uv;
        const float incidence = float(1 - o_.incidence_weight + o_.incidence_weight * std::abs(denom));
        hit.reflectivity = world_.materials[tri.material].intrinsicReflectivity(uv) * incidence;
        return true;
    }

    /** A beam with its divergence footprint: the return's range and reflectivity (before fall-off and gain). */
    bool beam(const Eigen::Vector3f& d, Hit& out, SweepStats& st) const
    {
        ++st.rays;
        Hit centre;
        if (!cast(d, centre)) return ++st.no_return, false;
        if (centre.glass) return ++st.glass_dropped, false;
        const float half = float(0.5e-3 * o_.sweep_divergence_mrad);
        out = centre;
        if (half <= 0) return true;
        const Eigen::Vector3f u = d.unitOrthogonal(), v = d.cross(u);
        float r_min = centre.range, r_max = centre.range, r_sum = centre.range, refl_sum = centre.reflectivity;
        float sub[4];
        int n = 1;
        Hit near = centre;
        const Eigen::Vector3f offsets[4] = {u, -u, v, -v};
        for (int i = 0; i < 4; ++i)
        {
            Hit h;
            sub[i] = -1;
            if (!cast((d + half * offsets[i]).normalized(), h) || h.glass) continue;
            sub[i] = h.range;
            r_min = std::min(r_min, h.range), r_max = std::max(r_max, h.range);
            r_sum += h.range, refl_sum += h.reflectivity, ++n;
            if (h.range < near.range) near = h;
        }
        // An edge: a footprint that is not one plane (on a plane, even a grazing one, opposite rays average to the
        // centre's range) or that partly hits nothing.
        const bool edge = n < 5 || std::abs(sub[0] + sub[1] - 2 * centre.range) > 0.02f ||
                          std::abs(sub[2] + sub[3] - 2 * centre.range) > 0.02f;
        if (!edge) return true;
        if (r_max - r_min > o_.sweep_mixed_max_gap_m)
        {
            out = near;
            return true;
        }
        ++st.mixed;
        out.range = r_sum / float(n);
        out.reflectivity = refl_sum / float(n);
        return true;
    }

   private:
    const World& world_;
    const Mesh& moving_;
    const MappingScene& scene_;
    const CubeMap& cube_;
    const LidarOptions& o_;
};

/** One firing: its direction in the LiDAR frame, its time after the sweep's start, its ring. */
struct Firing
{
    Eigen::Vector3f d;
    float dt;
    uint16_t ring;
};

std::vector<Firing> spinningPattern(const LidarOptions& o)
{
    std::vector<Firing> out;
    const int beams = o.sweep_beams, steps = o.sweep_azimuth_steps;
    for (int a = 0; a < steps; ++a)
    {
        const double az = 2 * M_PI * a / steps;
        for (int b = 0; b < beams; ++b)
        {
            const double el =
                (o.sweep_min_elevation_deg +
                 (beams > 1 ? (o.sweep_max_elevation_deg - o.sweep_min_elevation_deg) * b / (beams - 1) : 0.0)) *
                M_PI / 180;
            out.push_back({Eigen::Vector3f(float(std::cos(el) * std::cos(az)), float(std::cos(el) * std::sin(az)),
                                           float(std::sin(el))),
                           float(a / (steps * o.sweep_rate_hz)), uint16_t(b)});
        }
    }
    return out;
}

/** Livox-like: two prisms turning in opposite directions at incommensurate rates trace a rosette that never
 *  repeats; t0 is the sweep's start on the run's clock. */
std::vector<Firing> rosettePattern(const LidarOptions& o, double t0)
{
    std::vector<Firing> out;
    const auto n = size_t(o.rosette_points_per_s / o.sweep_rate_hz);
    const double delta = o.rosette_fov_deg * M_PI / 180 / 4, w1 = 2 * M_PI * 121.57, w2 = -2 * M_PI * 77.73;
    for (size_t j = 0; j < n; ++j)
    {
        const double dt = double(j) / o.rosette_points_per_s, t = t0 + dt;
        const double ax = delta * (std::cos(w1 * t) + std::cos(w2 * t)),
                     ay = delta * (std::sin(w1 * t) + std::sin(w2 * t));
        out.push_back({Eigen::Vector3f(1.f, float(std::tan(ax)), float(std::tan(ay))).normalized(), float(dt), 0});
    }
    return out;
}

map::LidarScan simulateSweep(const World& world, const MappingScene& scene, const MappingRun& run,
                             const LidarOptions& o, const std::vector<float>& ring_gain, size_t k, uint64_t seed,
                             const std::vector<Firing>& spinning, SweepStats& st)
{
    const double period = 1.0 / o.sweep_rate_hz, t0 = double(k) * period;
    const Mesh moving = scene.meshAt(t0 + 0.5 * period);
    CubeMap cube;
    // on this thread: the machine is shared
    renderCubeMap(world.mesh, moving, run.pose(t0 + 0.5 * period).translation().cast<float>(), o.sweep_cubemap_px,
                  cube);
    const SweepCaster caster(world, moving, scene, cube, o);
    const std::vector<Firing> rosette =
        o.sweep_pattern == SweepPattern::rosette ? rosettePattern(o, t0) : std::vector<Firing>{};
    const std::vector<Firing>& firings = o.sweep_pattern == SweepPattern::rosette ? rosette : spinning;
    std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ull + k);
    std::normal_distribution<float> normal(0.f, 1.f);
    map::LidarScan scan;
    char name[40];
    std::snprintf(name, sizeof(name), "sweep_%06zu", k);
    scan.name = name;
    Eigen::Isometry3f T_world_lidar = Eigen::Isometry3f::Identity();
    float pose_dt = -1;
    for (const Firing& f : firings)
    {
        if (f.dt != pose_dt)  // a spinning LiDAR fires a column of beams at once
            T_world_lidar = run.pose(t0 + f.dt).cast<float>(), pose_dt = f.dt;
        const Eigen::Vector3f d = T_world_lidar.linear() * f.d;
        Hit hit;
        if (!caster.beam(d, hit, st)) continue;
        // The return as the LiDAR at the firing's time sees it (the cube's centre is the mid-sweep position).
        Eigen::Vector3f q = T_world_lidar.inverse() * (cube.centre + hit.range * d);
        const float range = q.norm();
        if (range < 0.05f) continue;
        q *= (range + normal(rng) * float(o.sweep_range_noise_mm * 1e-3)) / range;
        const float falloff = 1.f / (1.f + std::pow(range / float(o.range_falloff_m), 2.f));
        const float signal = hit.reflectivity * falloff * ring_gain[f.ring] + normal(rng) * float(o.reflectivity_noise);
        scan.points.push_back(q);
        scan.intensity.push_back(std::round(255.f * std::clamp(signal, 0.f, 1.f)));
        scan.time_s.push_back(f.dt);
        scan.ring.push_back(f.ring);
        ++st.returns;
        st.transient_returns += hit.moving;
    }
    return scan;
}
}  // namespace

SimulatedSweeps simulateSweeps(const World& world, const MappingScene& scene, const MappingRun& run,
                               const LidarOptions& o, uint64_t seed, SweepStats* stats)
{
    SweepStats st;
    std::mt19937_64 rng(seed ^ 0x6A1Bull);
    std::normal_distribution<float> normal(0.f, 1.f);
    std::vector<float> ring_gain(size_t(std::max(1, o.sweep_beams)));
    for (float& g : ring_gain) g = std::exp(normal(rng) * float(o.sweep_ring_gain_error));
    const std::vector<Firing> spinning =
        o.sweep_pattern == SweepPattern::spinning ? spinningPattern(o) : std::vector<Firing>{};
    // A sweep ends before the run does: the last one's poses are all inside it.
    const auto n = size_t(std::max(0.0, std::floor(run.duration() * o.sweep_rate_hz) - 1));
    st.sweeps_run = n;
    SimulatedSweeps out;
    for (size_t k = 0; k < n; k += size_t(o.sweep_every))
    {
        out.scans.push_back(simulateSweep(world, scene, run, o, ring_gain, k, seed, spinning, st));
        out.stamps.push_back(double(k) / o.sweep_rate_hz);
    }
    st.sweeps_used = out.scans.size();
    if (stats) *stats = st;
    return out;
}

map::ScanPoses mappingPoses(const MappingRun& run, const SimulatedSweeps& sweeps)
{
    map::ScanPoseOptions po;
    po.format = map::TrajectoryFormat::Bag;
    po.times = map::ScanTimeSource::Stamps;
    po.trajectory = "the simulated mapping run's odometry";
    po.poses.header = "T_world_lidar of the simulated mapping run, with a LiDAR-inertial odometry's error";
    for (size_t i = 0; i < run.t.size(); ++i)
        po.poses.poses.push_back({run.t[i], core::fromIsometry(run.T_world_lidar_est[i])});
    std::vector<std::string> names;
    for (const map::LidarScan& s : sweeps.scans) names.push_back(s.name);
    return map::ScanPoses(po, names, sweeps.stamps);
}

map::MapBuildOptions sweptMapBuildOptions(const LidarOptions& o, const std::string& output_name)
{
    map::MapBuildOptions mb;
    mb.voxel_size_m = o.sweep_voxel_m;
    mb.min_range_m = o.sweep_min_range_m;
    mb.output = output_name;
    return mb;
}

SweptMap buildSweptMap(const World& world, const std::vector<Eigen::Vector3f>& waypoints, const LidarOptions& o,
                       uint64_t seed, const std::string& output_name)
{
    o.check("[Lidar]");
    SweptMap out;
    auto clock = std::chrono::steady_clock::now();
    out.run = planMappingRun(world, waypoints, o, seed);
    out.scene = makeMappingScene(world, out.run, o, seed);
    SimulatedSweeps sweeps = simulateSweeps(world, out.scene, out.run, o, seed, &out.sweeps);
    out.simulate_s = secondsSince(clock);
    clock = std::chrono::steady_clock::now();
    const map::ScanPoses poses = mappingPoses(out.run, sweeps);
    out.build = map::buildMap(sweptMapBuildOptions(o, output_name), sweeps, poses);
    out.build_s = secondsSince(clock);
    clock = std::chrono::steady_clock::now();
    out.quality = evaluateSweptMap(world, out.scene, out.build.map, out.build.removed);
    out.evaluate_s = secondsSince(clock);
    return out;
}

std::string SweptMap::summary() const
{
    const auto [drift_m, drift_deg] = mappingRunDrift(run);
    const SweptMapQuality& q = quality;
    std::ostringstream s;
    s.precision(3);
    s << "swept map (simulated): mapping run " << run.length_m << " m, " << run.duration() << " s, "
      << run.loop_closure_t.size() << " loop closures, pose error up to " << drift_m * 100 << " cm / " << drift_deg
      << " deg; " << sweeps.sweeps_used << " of " << sweeps.sweeps_run << " sweeps, " << build.points_read
      << " returns (" << sweeps.mixed << " mixed, " << sweeps.glass_dropped << " lost on glass, "
      << sweeps.transient_returns << " on people/furniture); map-build: " << q.points << " points, "
      << build.removed.size() << " carved; error to the true surfaces median " << q.median_error_m * 1000 << " mm, p95 "
      << q.p95_error_m * 1000 << " mm, " << q.share_beyond_10cm * 100 << " % beyond 10 cm; coverage "
      << q.coverage * 100 << " % (floor " << q.coverage_by_part[0] * 100 << ", ceiling " << q.coverage_by_part[1] * 100
      << ", outer walls " << q.coverage_by_part[2] * 100 << ", the rest " << q.coverage_by_part[3] * 100
      << "); people points removed " << q.person_points_removed << " of " << q.person_points_fused
      << ", furniture points removed " << q.furniture_points_removed << " of " << q.furniture_points_fused
      << "; glass points " << q.glass_points << "; time: sweeps " << simulate_s << " s, map-build " << build_s
      << " s, evaluation " << evaluate_s << " s";
    return s.str();
}

}  // namespace quasiloc::sim
