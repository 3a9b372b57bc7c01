// The ground robot's tour and how it drives it (robot_motion.h).
#include <algorithm>
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/sim/robot_motion.h>
#include <random>

namespace quasiloc::sim
{
namespace
{
using Rng = std::mt19937_64;
constexpr double kPi = 3.14159265358979323846;

double wrapAngle(double a) { return std::atan2(std::sin(a), std::cos(a)); }

/** One primitive of the drive: stand still, turn in place by `amount` rad, or drive `amount` m straight ahead. */
struct Phase
{
    enum Kind
    {
        stand,
        turn,
        drive
    } kind = stand;
    double t0 = 0, duration = 0;
    Eigen::Vector2d p0 = Eigen::Vector2d::Zero();
    double yaw0 = 0, amount = 0;
    double cruise = 0, ramp_s = 0;  ///< drive: cruise speed and the length of each speed ramp
};

/** Distance along a drive phase after tau seconds, and speed and acceleration there (raised-cosine ramps). */
void driveProfile(const Phase& ph, double tau, double& s, double& v, double& a)
{
    const double Ta = ph.ramp_s, vc = ph.cruise, T = ph.duration;
    auto up = [&](double u, double& su, double& vu, double& au) {  // 0 <= u <= Ta
        su = 0.5 * vc * (u - Ta / kPi * std::sin(kPi * u / Ta));
        vu = 0.5 * vc * (1 - std::cos(kPi * u / Ta));
        au = 0.5 * vc * kPi / Ta * std::sin(kPi * u / Ta);
    };
    tau = std::clamp(tau, 0.0, T);
    if (tau <= Ta)
        up(tau, s, v, a);
    else if (tau >= T - Ta)
    {
        up(T - tau, s, v, a);
        s = ph.amount - s;
        a = -a;
    }
    else
    {
        s = 0.5 * vc * Ta + vc * (tau - Ta);
        v = vc;
        a = 0;
    }
}

PlanarState evaluate(const Phase& ph, double t)
{
    PlanarState st;
    st.t = t;
    st.p = ph.p0;
    st.yaw = ph.yaw0;
    const double tau = std::clamp(t - ph.t0, 0.0, ph.duration);
    if (ph.kind == Phase::turn)
    {
        const double u = tau / ph.duration;
        st.yaw = ph.yaw0 + ph.amount * (u - std::sin(2 * kPi * u) / (2 * kPi));
        st.yaw_rate = ph.amount / ph.duration * (1 - std::cos(2 * kPi * u));
    }
    else if (ph.kind == Phase::drive)
    {
        double s = 0;
        driveProfile(ph, tau, s, st.speed, st.accel);
        st.p = ph.p0 + s * Eigen::Vector2d(std::cos(ph.yaw0), std::sin(ph.yaw0));
    }
    return st;
}

/** Sums of sinusoids with frequencies drawn in the given bands and random phases. */
struct Vibration
{
    std::vector<double> freq, phase, weight;
    Vibration(Rng& rng, const std::vector<std::pair<double, double>>& bands, const std::vector<double>& weights)
    {
        std::uniform_real_distribution<double> u01(0, 1);
        for (size_t i = 0; i < bands.size(); ++i)
        {
            freq.push_back(bands[i].first + u01(rng) * (bands[i].second - bands[i].first));
            phase.push_back(2 * kPi * u01(rng));
            weight.push_back(weights[i]);
        }
    }
    double at(double t) const
    {
        double v = 0;
        for (size_t i = 0; i < freq.size(); ++i) v += weight[i] * std::sin(2 * kPi * freq[i] * t + phase[i]);
        return v;
    }
};

void checkOptions(const GroundRobotOptions& o, const std::string& in)
{
    core::require(o.min_speed_m_s > 0 && o.max_speed_m_s >= o.min_speed_m_s, in + " robot_max_speed_m_s",
                  "must be >= robot_min_speed_m_s > 0");
    core::require(o.max_accel_m_s2 > 0 && o.max_yaw_rate_deg_s > 0 && o.sample_rate_hz > 0, in,
                  "robot_max_accel_m_s2, robot_max_yaw_rate_deg_s and the sample rate must be positive");
    core::require(o.stop_max_s >= o.stop_min_s, in + " robot_stop_max_s", "must be >= robot_stop_min_s");
}

/** The drive's phases: initial stand, then per segment a turn in place, the drive and sometimes a wait. */
std::vector<Phase> makePhases(const std::vector<Eigen::Vector2d>& wps, const GroundRobotOptions& o, Rng& rng,
                              GroundRobotMotion& m)
{
    std::uniform_real_distribution<double> u01(0, 1);
    std::vector<Phase> phases;
    double t = 0;
    auto push = [&](Phase ph) {
        ph.t0 = t;
        t += ph.duration;
        phases.push_back(ph);
    };
    Eigen::Vector2d p = wps.front();
    double yaw = 0;
    for (size_t i = 1; i < wps.size(); ++i)
        if ((wps[i] - p).norm() > 1e-6)
        {
            yaw = std::atan2(wps[i].y() - p.y(), wps[i].x() - p.x());
            break;
        }
    push({Phase::stand, 0, o.standing_s, p, yaw});
    const double max_rate = o.max_yaw_rate_deg_s * kPi / 180;
    for (size_t i = 1; i < wps.size(); ++i)
    {
        const Eigen::Vector2d d = wps[i] - p;
        const double len = d.norm();
        if (len < 1e-6) continue;
        const double dyaw = wrapAngle(std::atan2(d.y(), d.x()) - yaw);
        if (std::abs(dyaw) > 1e-3)
        {
            push({Phase::turn, 0, std::max(0.8, 2 * std::abs(dyaw) / max_rate), p, yaw, dyaw});
            if (std::abs(dyaw) > 10 * kPi / 180) ++m.turns_in_place;
            yaw = wrapAngle(yaw + dyaw);
        }
        Phase drive{Phase::drive, 0, 0, p, yaw, len};
        drive.cruise = o.min_speed_m_s + u01(rng) * (o.max_speed_m_s - o.min_speed_m_s);
        drive.ramp_s = kPi * drive.cruise / (2 * o.max_accel_m_s2);
        if (len < drive.cruise * drive.ramp_s)  // too short to reach the cruise speed: peak lower, no cruise
        {
            drive.cruise = std::sqrt(2 * o.max_accel_m_s2 * len / kPi);
            drive.ramp_s = kPi * drive.cruise / (2 * o.max_accel_m_s2);
        }
        drive.duration = len / drive.cruise + drive.ramp_s;
        push(drive);
        m.length_m += len;
        p = wps[i];
        if (u01(rng) < o.stop_probability)
        {
            push({Phase::stand, 0, o.stop_min_s + u01(rng) * (o.stop_max_s - o.stop_min_s), p, yaw});
            ++m.stops;
        }
    }
    push({Phase::stand, 0, 1.0, p, yaw});
    return phases;
}
}  // namespace

mrpt::poses::CPose3D baseToCamera(const GroundRobotOptions& o)
{
    Eigen::Matrix3d R_base_cam;
    R_base_cam.col(0) = Eigen::Vector3d(0, -1, 0);  // cam x: right
    R_base_cam.col(1) = Eigen::Vector3d(0, 0, -1);  // cam y: down
    R_base_cam.col(2) = Eigen::Vector3d(1, 0, 0);   // cam z: forward
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = R_base_cam;
    T.translation() = Eigen::Vector3d(o.camera_forward_m, 0, o.camera_height_m);
    return core::fromIsometry(T);
}

std::vector<Eigen::Vector2d> planFloorTour(const FloorLayout& l, const GroundRobotOptions& o, double min_duration_s,
                                           uint64_t seed)
{
    Rng rng(seed * 0xD1342543DE82EF95ull + 0x9E3779B97F4A7C15ull);
    std::uniform_real_distribution<double> u01(0, 1);
    const double end_margin = 1.2, first_leg = 6.0, room_margin = 1.0;
    std::vector<const FloorRoom*> rooms;
    for (const FloorRoom& r : l.rooms) rooms.push_back(&r);
    std::sort(rooms.begin(), rooms.end(), [](const auto* a, const auto* b) { return a->door_x < b->door_x; });
    auto inside_door = [&](const FloorRoom& r) {
        return Eigen::Vector2d(r.door_x, r.side * (l.corridor_half_width + 1.0));
    };
    auto room_point = [&](const FloorRoom& r) {
        const Eigen::AlignedBox2d& b = r.box;
        return Eigen::Vector2d(b.min().x() + room_margin + u01(rng) * (b.sizes().x() - 2 * room_margin),
                               b.min().y() + room_margin + u01(rng) * (b.sizes().y() - 2 * room_margin));
    };
    std::vector<Eigen::Vector2d> wps;
    double x = end_margin;
    int dir = 1;
    if (o.start_in_corridor)
        wps.push_back({end_margin, 0});
    else
    {
        // Near the far wall of a room, heading for its door, then out into the corridor.
        const FloorRoom& r = *rooms[static_cast<size_t>(u01(rng) * rooms.size()) % rooms.size()];
        Eigen::Vector2d p = room_point(r);
        p.y() = r.side > 0 ? r.box.max().y() - room_margin : r.box.min().y() + room_margin;
        wps.push_back(p);
        wps.push_back(inside_door(r));
        wps.push_back({r.door_x, 0});
        x = r.door_x;
        dir = x < 0.5 * l.corridor_length ? 1 : -1;  // the longer way along the corridor first
    }
    // Duration estimate: a mean speed of the speed range's middle over the path, ~3 s per waypoint for ramps,
    // turns and waits.
    const double mean_speed = 0.5 * (o.min_speed_m_s + o.max_speed_m_s);
    double estimate = o.standing_s;
    for (size_t i = 1; i < wps.size(); ++i) estimate += (wps[i] - wps[i - 1]).norm() / mean_speed + 3.0;
    auto add = [&](const Eigen::Vector2d& p) {
        estimate += (p - wps.back()).norm() / mean_speed + 3.0;
        wps.push_back(p);
    };
    while (estimate < min_duration_s + 5.0)
    {
        bool visited = false;
        for (size_t k = 0; k < rooms.size() && estimate < min_duration_s + 5.0; ++k)
        {
            const FloorRoom& r = *rooms[dir > 0 ? k : rooms.size() - 1 - k];
            const double ahead = dir * (r.door_x - x);
            const bool first = wps.size() == 1;
            if (ahead < (first ? first_leg : 1.0) || u01(rng) > 0.5) continue;
            add({r.door_x, 0});
            add(inside_door(r));
            const int points = u01(rng) < 0.5 ? 1 : 2;
            for (int i = 0; i < points; ++i) add(room_point(r));
            add(inside_door(r));
            add({r.door_x, 0});
            x = r.door_x;
            visited = true;
        }
        // To the corridor's end, then back the other way.
        const double end = dir > 0 ? l.corridor_length - end_margin : end_margin;
        if (!visited || std::abs(end - x) > 1.0) add({end, 0});
        x = end;
        dir = -dir;
    }
    return wps;
}

GroundRobotMotion driveWaypoints(const std::vector<Eigen::Vector2d>& wps, const GroundRobotOptions& o, double t0,
                                 uint64_t seed, const std::string& input)
{
    checkOptions(o, input);
    core::require(wps.size() >= 2, input, "a robot tour needs at least two waypoints");
    Rng rng(seed * 0x9FB21C651E98DF25ull + 17);
    GroundRobotMotion m;
    m.waypoints = wps;
    const std::vector<Phase> phases = makePhases(wps, o, rng, m);
    const Vibration bounce(rng, {{1.5, 2.5}, {3.0, 4.5}, {6.0, 8.0}}, {1.0, 0.5, 0.15});
    const Vibration roll(rng, {{2.0, 3.0}, {4.5, 6.0}}, {1.0, 0.5});
    const Vibration pitch(rng, {{2.0, 3.0}, {4.5, 6.0}}, {1.0, 0.5});
    const double total = phases.back().t0 + phases.back().duration;
    const double max_rate = o.max_yaw_rate_deg_s * kPi / 180, deg = kPi / 180;
    m.T_world_base.header = "T_world_base of the simulated ground robot (x forward, y left, z up)";
    size_t ph = 0;
    for (int64_t k = 0;; ++k)
    {
        const double t = static_cast<double>(k) / o.sample_rate_hz;
        if (t > total + 1e-9) break;
        while (ph + 1 < phases.size() && t >= phases[ph + 1].t0) ++ph;
        PlanarState st = evaluate(phases[ph], t);
        const double effort = std::min(1.0, std::max(st.speed / o.max_speed_m_s, std::abs(st.yaw_rate) / max_rate));
        const double z = effort * o.vibration_z_mm * 1e-3 * bounce.at(t);
        const double r = effort * o.vibration_tilt_deg * deg * roll.at(t);
        const double p = effort * o.vibration_tilt_deg * deg * pitch.at(t) - o.pitch_per_accel_deg * deg * st.accel;
        st.t = t0 + t;
        m.planar.push_back(st);
        m.T_world_base.poses.push_back({t0 + t, mrpt::poses::CPose3D(st.p.x(), st.p.y(), z, st.yaw, p, r)});
    }
    if (o.start_moving)
    {
        // The first frame at the first drive's cruise (the end of its speed ramp).
        const auto first =
            std::find_if(phases.begin(), phases.end(), [](const Phase& p) { return p.kind == Phase::drive; });
        m.first_frame_offset_s = first->t0 + first->ramp_s;
    }
    else
        m.first_frame_offset_s = std::min(0.5, 0.5 * o.standing_s);
    return m;
}

GroundRobotMotion generateGroundRobotMotion(const FloorLayout& layout, const GroundRobotOptions& options,
                                            double min_duration_s, double t0, uint64_t seed, const std::string& input)
{
    checkOptions(options, input);
    // The tour is planned for the frames' span plus the time before the first frame (a moving start begins after
    // the first segment's ramp, ~4 s in).
    GroundRobotMotion m;
    double need = min_duration_s + options.standing_s + 6.0;
    for (int attempt = 0; attempt < 4; ++attempt)
    {
        m = driveWaypoints(planFloorTour(layout, options, need, seed), options, t0, seed, input);
        const double span = m.T_world_base.poses.back().t - m.T_world_base.poses.front().t - m.first_frame_offset_s;
        if (span >= min_duration_s) break;
        need += min_duration_s - span + 5.0;
    }
    for (size_t i = 1; i + 1 < m.waypoints.size(); ++i)  // entering a room: corridor point followed by a door point
        if (std::abs(m.waypoints[i].y()) < 1e-9 && std::abs(m.waypoints[i + 1].y()) > layout.corridor_half_width &&
            std::abs(m.waypoints[i - 1].y()) < 1e-9)
            ++m.rooms_visited;
    return m;
}

}  // namespace quasiloc::sim
