// The car's route through the campus and how it drives it (car_motion.h).
#include <algorithm>
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/sim/car_motion.h>
#include <quasiloc/sim/robot_motion.h>
#include <random>

namespace quasiloc::sim
{
namespace
{
using Rng = std::mt19937_64;
using Eigen::Vector2d;
constexpr double kDs = 0.05;  ///< grid of the path and of the speed profile, metres

/** The driven path on a kDs grid: position, heading (unwrapped) and curvature. */
struct DensePath
{
    std::vector<Vector2d> p;
    std::vector<double> yaw, curvature;
    std::vector<size_t> stop_candidates;  ///< grid index before each intersection where the car may stop

    void push(const Vector2d& q, double heading, double kappa)
    {
        if (!yaw.empty()) heading = yaw.back() + std::remainder(heading - yaw.back(), 2 * M_PI);
        p.push_back(q);
        yaw.push_back(heading);
        curvature.push_back(kappa);
    }
    /** A straight piece from the last point to q (the last point is its start). */
    void straightTo(const Vector2d& q)
    {
        const Vector2d a = p.back(), d = q - a;
        const double len = d.norm();
        const auto n = size_t(std::ceil(len / kDs));
        for (size_t i = 1; i <= n; ++i) push(a + d * (double(i) / double(n)), std::atan2(d.y(), d.x()), 0);
    }
    /** An arc from the last point, heading h0, turning by `angle` (signed, left positive) on radius r. */
    void arc(double h0, double angle, double r)
    {
        const Vector2d a = p.back(), to_centre = (angle > 0 ? 1 : -1) * Vector2d(-std::sin(h0), std::cos(h0));
        const Vector2d c = a + r * to_centre;
        const auto n = size_t(std::ceil(std::abs(angle) * r / kDs));
        for (size_t i = 1; i <= n; ++i)
        {
            const double phi = angle * double(i) / double(n), h = h0 + phi;
            const Vector2d from_centre = -r * (angle > 0 ? 1 : -1) * Vector2d(-std::sin(h), std::cos(h));
            push(c + from_centre, h, (angle > 0 ? 1 : -1) / r);
        }
    }
};

Vector2d rightOf(const Vector2d& d) { return Vector2d(d.y(), -d.x()); }

/** The lane (offset right of the centreline) with its corners rounded; stop candidates before inner intersections. */
DensePath lanePath(const std::vector<Vector2d>& nodes, const CarOptions& o, const CampusLayout& l,
                   const std::string& in)
{
    const size_t n = nodes.size();
    std::vector<Vector2d> dir(n - 1);
    for (size_t i = 0; i + 1 < n; ++i) dir[i] = (nodes[i + 1] - nodes[i]).normalized();
    auto lane = [&](size_t i) {  // the lane's corner at node i (the mitre of the two offset segments)
        if (i == 0) return Vector2d(nodes[0] + o.lane_offset_m * rightOf(dir[0]));
        if (i + 1 == n) return Vector2d(nodes[i] + o.lane_offset_m * rightOf(dir[i - 1]));
        const Vector2d r1 = rightOf(dir[i - 1]), r2 = rightOf(dir[i]);
        return Vector2d(nodes[i] + o.lane_offset_m * (r1 + r2) / (1 + r1.dot(r2)));
    };
    DensePath path;
    path.push(lane(0), std::atan2(dir[0].y(), dir[0].x()), 0);
    for (size_t i = 1; i + 1 < n; ++i)
    {
        const double angle =
            std::remainder(std::atan2(dir[i].y(), dir[i].x()) - std::atan2(dir[i - 1].y(), dir[i - 1].x()), 2 * M_PI);
        const double tangent = std::abs(angle) > 1e-6 ? o.turn_radius_m * std::tan(0.5 * std::abs(angle)) : 0.0;
        core::require(tangent <= 0.45 * (l.pitch - 2 * o.lane_offset_m), in + " car_turn_radius_m",
                      "is too large for the blocks (campus_block_size_m)");
        const Vector2d corner = lane(i);
        const Vector2d arc_start = corner - tangent * dir[i - 1];
        // The stop: before the zebra crossing, street_half + 4 m before the intersection's centre.
        const double back = l.street_half + 4.0 - tangent;
        if (back > 0)
        {
            path.straightTo(arc_start - back * dir[i - 1]);
            path.stop_candidates.push_back(path.p.size() - 1);
        }
        path.straightTo(arc_start);
        if (tangent > 0) path.arc(path.yaw.back(), angle, o.turn_radius_m);
    }
    path.straightTo(lane(n - 1));
    return path;
}

void checkOptions(const CarOptions& o, const std::string& in)
{
    core::require(o.max_speed_m_s > 0 && o.turn_speed_m_s > 0 && o.max_accel_m_s2 > 0 && o.sample_rate_hz > 0, in,
                  "car_max_speed_m_s, car_turn_speed_m_s, car_max_accel_m_s2 and the sample rate must be positive");
    core::require(o.stop_max_s >= o.stop_min_s, in + " car_stop_max_s", "must be >= car_stop_min_s");
}
}  // namespace

std::vector<Vector2d> planCarRoute(const CampusLayout& l, const CarOptions& o, uint64_t seed)
{
    Rng rng(seed * 0x2545F4914F6CDD1Dull + 0xC4A2ull);
    std::uniform_real_distribution<double> u01(0, 1);
    const int N = l.blocks;
    Eigen::Vector2i node(int(u01(rng) * (N + 1)) % (N + 1), int(u01(rng) * (N + 1)) % (N + 1));
    auto valid = [&](const Eigen::Vector2i& q) { return q.x() >= 0 && q.y() >= 0 && q.x() <= N && q.y() <= N; };
    const Eigen::Vector2i dirs[4] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    int heading = int(u01(rng) * 4) % 4;
    while (!valid(node + dirs[heading])) heading = (heading + 1) % 4;
    std::vector<Vector2d> route = {Vector2d(l.street(node.x()), l.street(node.y()))};
    double length = 0;
    while (length < o.route_length_m)
    {
        node += dirs[heading];
        route.emplace_back(l.street(node.x()), l.street(node.y()));
        length += l.pitch;
        // Next: straight on (weight 2), left or right (weight 1 each), among the streets that exist.
        const int options[3] = {heading, (heading + 1) % 4, (heading + 3) % 4};
        const double weights[3] = {2, 1, 1};
        double total = 0;
        for (int k = 0; k < 3; ++k) total += valid(node + dirs[options[k]]) ? weights[k] : 0;
        double pick = u01(rng) * total;
        for (int k = 0; k < 3; ++k)
        {
            if (!valid(node + dirs[options[k]])) continue;
            heading = options[k];
            if ((pick -= weights[k]) <= 0) break;
        }
    }
    return route;
}

CarMotion driveCarRoute(const CampusLayout& l, const std::vector<Vector2d>& nodes, const CarOptions& o, double t0,
                        uint64_t seed, const std::string& in)
{
    checkOptions(o, in);
    core::require(nodes.size() >= 2, in, "a car route needs two intersections or more");
    const DensePath path = lanePath(nodes, o, l, in);
    const size_t n = path.p.size();
    Rng rng(seed * 0x9E3779B97F4A7C15ull + 0xCA5ull);
    std::uniform_real_distribution<double> u01(0, 1);
    CarMotion m;
    m.intersections = nodes;
    // Speed limits on the grid, then the fastest profile within the acceleration bound.
    std::vector<double> v(n, o.max_speed_m_s), wait(n, 0.0);
    for (size_t i = 0; i < n; ++i)
        if (path.curvature[i] != 0) v[i] = std::min(o.max_speed_m_s, o.turn_speed_m_s);
    for (size_t i = 1; i < n; ++i)
        if (path.curvature[i] != 0 && path.curvature[i - 1] == 0) ++m.turns;
    for (size_t i : path.stop_candidates)
        if (u01(rng) < o.stop_probability)
        {
            v[i] = 0;
            wait[i] = o.stop_min_s + u01(rng) * (o.stop_max_s - o.stop_min_s);
            ++m.stops;
        }
    v.front() = v.back() = 0;
    wait.front() = o.standing_s;
    wait.back() = o.standing_s;
    for (size_t i = 1; i < n; ++i) v[i] = std::min(v[i], std::sqrt(v[i - 1] * v[i - 1] + 2 * o.max_accel_m_s2 * kDs));
    for (size_t i = n - 1; i-- > 0;) v[i] = std::min(v[i], std::sqrt(v[i + 1] * v[i + 1] + 2 * o.max_accel_m_s2 * kDs));
    // Arrival and departure time at every grid point (they differ where the car waits).
    std::vector<double> arrive(n), depart(n), accel(n, 0.0);
    arrive[0] = 0;
    depart[0] = wait[0];
    for (size_t i = 0; i + 1 < n; ++i)
    {
        const double ds = (path.p[i + 1] - path.p[i]).norm();
        accel[i] = ds > 0 ? (v[i + 1] * v[i + 1] - v[i] * v[i]) / (2 * ds) : 0.0;
        arrive[i + 1] = depart[i] + (v[i] + v[i + 1] > 0 ? 2 * ds / (v[i] + v[i + 1]) : 0.0);
        depart[i + 1] = arrive[i + 1] + wait[i + 1];
        m.length_m += ds;
        m.top_speed_m_s = std::max(m.top_speed_m_s, v[i + 1]);
    }
    m.duration_s = depart.back();
    m.first_frame_offset_s = std::min(0.5, 0.5 * o.standing_s);
    const double pitch_k = o.pitch_per_accel_deg * M_PI / 180, roll_k = o.roll_per_lateral_accel_deg * M_PI / 180;
    size_t i = 0;
    const auto samples = size_t(std::floor(m.duration_s * o.sample_rate_hz)) + 1;
    for (size_t k = 0; k < samples; ++k)
    {
        const double t = double(k) / o.sample_rate_hz;
        while (i + 1 < n && arrive[i + 1] <= t) ++i;
        double f = 0, speed = 0, a = 0;  // fraction of the way to i + 1, speed, acceleration
        if (t > depart[i] && i + 1 < n)
        {
            const double tau = t - depart[i], ds = (path.p[i + 1] - path.p[i]).norm();
            const double s = std::min(ds, v[i] * tau + 0.5 * accel[i] * tau * tau);
            f = ds > 0 ? s / ds : 0.0;
            speed = v[i] + accel[i] * tau;
            a = accel[i];
        }
        const size_t j = std::min(n - 1, i + 1);
        const Vector2d p = (1 - f) * path.p[i] + f * path.p[j];
        const double yaw = (1 - f) * path.yaw[i] + f * path.yaw[j];
        const double lateral = speed * speed * path.curvature[i];
        m.T_world_base.poses.push_back(
            {t0 + t, mrpt::poses::CPose3D(p.x(), p.y(), 0, yaw, -pitch_k * a, roll_k * lateral)});
    }
    m.T_world_base.header = "T_world_base of the car (base: x forward, y left, z up, on the road)";
    return m;
}

mrpt::poses::CPose3D carBaseToCamera(const CarOptions& o)
{
    GroundRobotOptions mount;
    mount.camera_height_m = o.camera_height_m;
    mount.camera_forward_m = o.camera_forward_m;
    return baseToCamera(mount);
}

}  // namespace quasiloc::sim
