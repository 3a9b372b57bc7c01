// The mapping run of the swept map (lidar_sweeps.h): the walk, its orientation and the odometry's drift.
#include <algorithm>
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/sim/lidar_sweeps.h>
#include <quasiloc/sim/world_builder.h>
#include <random>

namespace quasiloc::sim
{
namespace
{
constexpr double kPoseRate_hz = 100;

/** Two laps in a EuRoC room: an ellipse around it, then a figure eight through its middle, back to the start.
 *  Each lap's scale is the candidate with the most clearance from the geometry. */
std::vector<Eigen::Vector3f> roomLoops(const World& world, const LidarOptions& o)
{
    const Eigen::Vector3f c = world.room.center();
    const Eigen::Vector3f half = 0.5f * world.room.sizes();
    const float z = world.room.min().z() + float(0.5 * (o.sweep_min_height_m + o.sweep_max_height_m));
    auto lap = [&](float scale, bool eight) {
        std::vector<Eigen::Vector3f> pts;
        for (int i = 0; i <= 96; ++i)
        {
            const float a = float(2 * M_PI * i / 96);
            const float y = eight ? std::sin(a) * std::cos(a) * 2.f : std::sin(a);
            pts.emplace_back(c.x() + scale * half.x() * std::cos(a), c.y() + scale * half.y() * y, z);
        }
        return pts;
    };
    auto best_lap = [&](bool eight) {
        std::vector<Eigen::Vector3f> best;
        double best_clearance = -1;
        for (float scale : {0.25f, 0.3f, 0.35f, 0.4f, 0.45f, 0.5f})
        {
            std::vector<Eigen::Vector3f> pts = lap(scale, eight), probe;
            for (const Eigen::Vector3f& p : pts)
                for (double h : {o.sweep_min_height_m, o.sweep_max_height_m})
                    probe.emplace_back(p.x(), p.y(), world.room.min().z() + float(h));
            const double clearance = minClearance(world.mesh, probe, 1.0);
            // Prefer the larger loop (more of the room near the LiDAR) unless a smaller one is clearly safer.
            if (clearance > best_clearance + 0.05 || (clearance >= 0.5 && clearance >= best_clearance - 0.05))
                best = pts, best_clearance = clearance;
        }
        return best;
    };
    std::vector<Eigen::Vector3f> path = best_lap(false);
    const std::vector<Eigen::Vector3f> eight = best_lap(true);
    path.insert(path.end(), eight.begin(), eight.end());
    path.push_back(path.front());
    return path;
}

Eigen::Matrix3d expSO3(const Eigen::Vector3d& w)
{
    const double a = w.norm();
    return a < 1e-12 ? Eigen::Matrix3d::Identity() : Eigen::AngleAxisd(a, w / a).toRotationMatrix();
}

/** Loop closures: the run passes within 1 m of where it was 20 s or more before, at least 10 s after the last one. */
std::vector<double> detectLoopClosures(const MappingRun& run)
{
    std::vector<double> closures;
    const size_t step = size_t(kPoseRate_hz);  // 1 Hz
    for (size_t i = 0; i < run.t.size(); i += step)
    {
        if (!closures.empty() && run.t[i] - closures.back() < 10) continue;
        for (size_t j = 0; j < i && run.t[i] - run.t[j] >= 20; j += step)
            if ((run.T_world_lidar[i].translation() - run.T_world_lidar[j].translation()).norm() < 1.0)
            {
                closures.push_back(run.t[i]);
                break;
            }
    }
    return closures;
}

/** The odometry's error at the sweep rate: a 6-D random walk, a Brownian bridge between loop closures, scaled. */
void addDrift(MappingRun& run, const LidarOptions& o, uint64_t seed)
{
    const double dt = 1.0 / o.sweep_rate_hz;
    const auto n = size_t(std::floor(run.duration() / dt)) + 2;
    std::mt19937_64 rng(seed ^ 0xD81F7ull);
    std::normal_distribution<double> normal(0, 1);
    std::vector<Eigen::Matrix<double, 6, 1>> walk(n, Eigen::Matrix<double, 6, 1>::Zero());
    for (size_t k = 1; k < n; ++k)
        for (int d = 0; d < 6; ++d) walk[k][d] = walk[k - 1][d] + normal(rng);
    std::vector<size_t> anchors = {0};
    for (double t : run.loop_closure_t) anchors.push_back(std::min(n - 1, size_t(std::lround(t / dt))));
    std::vector<Eigen::Matrix<double, 6, 1>> err(n);
    for (size_t a = 0; a < anchors.size(); ++a)
    {
        const size_t k0 = anchors[a], k1 = a + 1 < anchors.size() ? anchors[a + 1] : n;
        for (size_t k = k0; k < k1 && k < n; ++k)
        {
            err[k] = walk[k] - walk[k0];
            if (a + 1 < anchors.size()) err[k] -= double(k - k0) / double(k1 - k0) * (walk[k1] - walk[k0]);
        }
    }
    double max_p = 1e-12, max_r = 1e-12;
    for (const auto& e : err) max_p = std::max(max_p, e.head<3>().norm()), max_r = std::max(max_r, e.tail<3>().norm());
    const double sp = o.sweep_drift_m / max_p, sr = o.sweep_drift_deg * M_PI / 180 / max_r;
    run.T_world_lidar_est.resize(run.t.size());
    for (size_t i = 0; i < run.t.size(); ++i)
    {
        const double x = run.t[i] / dt;
        const size_t k = std::min(n - 2, size_t(x));
        const double f = std::clamp(x - double(k), 0.0, 1.0);
        const Eigen::Matrix<double, 6, 1> e = (1 - f) * err[k] + f * err[k + 1];
        Eigen::Isometry3d T = run.T_world_lidar[i];
        T.linear() = expSO3(sr * e.tail<3>()) * T.linear();
        T.translation() += sp * e.head<3>();
        run.T_world_lidar_est[i] = T;
    }
}
}  // namespace

Eigen::Isometry3d MappingRun::pose(double s, bool estimated) const
{
    const std::vector<Eigen::Isometry3d>& T = estimated ? T_world_lidar_est : T_world_lidar;
    const double x = std::clamp(s * kPoseRate_hz, 0.0, double(T.size() - 1));
    const size_t k = std::min(T.size() - 2, size_t(x));
    const double f = x - double(k);
    Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
    const Eigen::Quaterniond q0(T[k].linear()), q1(T[k + 1].linear());
    out.linear() = q0.slerp(f, q1).toRotationMatrix();
    out.translation() = (1 - f) * T[k].translation() + f * T[k + 1].translation();
    return out;
}

MappingRun planMappingRun(const World& world, const std::vector<Eigen::Vector3f>& waypoints, const LidarOptions& o,
                          uint64_t seed)
{
    const std::vector<Eigen::Vector3f> path = waypoints.empty() ? roomLoops(world, o) : waypoints;
    core::require(path.size() >= 2, "[Lidar] map_source = sweeps", "the mapping run needs two waypoints or more");
    std::vector<double> along = {0};
    for (size_t i = 1; i < path.size(); ++i) along.push_back(along.back() + (path[i] - path[i - 1]).head<2>().norm());
    MappingRun run;
    run.length_m = along.back();
    const double duration = run.length_m / o.sweep_speed_m_s;
    const auto n = size_t(std::ceil(duration * kPoseRate_hz)) + 1;
    std::vector<Eigen::Vector3d> p(n);
    size_t seg = 0;
    const double floor_z = world.room.min().z();
    for (size_t i = 0; i < n; ++i)
    {
        const double s = std::min(run.length_m, double(i) / kPoseRate_hz * o.sweep_speed_m_s);
        while (seg + 2 < path.size() && along[seg + 1] < s) ++seg;
        const double len = std::max(1e-9, along[seg + 1] - along[seg]);
        const Eigen::Vector3d a = path[seg].cast<double>(), b = path[seg + 1].cast<double>();
        p[i] = a + std::clamp((s - along[seg]) / len, 0.0, 1.0) * (b - a);
        p[i].z() = floor_z + o.sweep_min_height_m +
                   (o.sweep_max_height_m - o.sweep_min_height_m) * (0.5 - 0.5 * std::cos(2 * M_PI * s / 9.0));
        run.t.push_back(double(i) / kPoseRate_hz);
    }
    // Heading over +-0.5 s, unwrapped, then averaged over 1 s: the carrier turns smoothly at the corners.
    std::vector<double> heading(n, 0);
    const size_t w = size_t(kPoseRate_hz / 2);
    for (size_t i = 0; i < n; ++i)
    {
        const Eigen::Vector3d d = p[std::min(n - 1, i + w)] - p[i >= w ? i - w : 0];
        heading[i] = d.head<2>().norm() > 1e-6 ? std::atan2(d.y(), d.x()) : (i ? heading[i - 1] : 0);
        if (i) heading[i] = heading[i - 1] + std::remainder(heading[i] - heading[i - 1], 2 * M_PI);
    }
    const double tilt = o.sweep_tilt_deg * M_PI / 180;
    for (size_t i = 0; i < n; ++i)
    {
        double yaw = 0;
        size_t count = 0;
        for (size_t j = i >= w ? i - w : 0; j <= std::min(n - 1, i + w); ++j) yaw += heading[j], ++count;
        yaw /= double(count);
        // The rosette looks forward only: the carrier looks around, +-60 deg over 10 s.
        if (o.sweep_pattern == SweepPattern::rosette) yaw += M_PI / 3 * std::sin(2 * M_PI * run.t[i] / 10);
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.linear() =
            (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(-tilt, Eigen::Vector3d::UnitY()))
                .toRotationMatrix();
        T.translation() = p[i];
        run.T_world_lidar.push_back(T);
    }
    run.loop_closure_t = detectLoopClosures(run);
    addDrift(run, o, seed);
    return run;
}

std::pair<double, double> mappingRunDrift(const MappingRun& run)
{
    double max_p = 0, max_r = 0;
    for (size_t i = 0; i < run.t.size(); ++i)
    {
        const Eigen::Isometry3d& a = run.T_world_lidar[i];
        const Eigen::Isometry3d& b = run.T_world_lidar_est[i];
        max_p = std::max(max_p, (a.translation() - b.translation()).norm());
        max_r = std::max(max_r, Eigen::AngleAxisd(b.linear() * a.linear().transpose()).angle() * 180 / M_PI);
    }
    return {max_p, max_r};
}

}  // namespace quasiloc::sim
