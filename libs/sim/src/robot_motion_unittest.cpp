#include <gtest/gtest.h>

#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/sim/imu_synthesizer.h>
#include <quasiloc/sim/robot_motion.h>
#include <quasiloc/sim/stereo_renderer.h>
#include <quasiloc/sim/world_builder.h>
#include <set>

using namespace quasiloc;

namespace
{
constexpr double kDeg = M_PI / 180;

struct RobotRun
{
    sim::FloorLayout layout;
    sim::GroundRobotMotion motion;
};

RobotRun makeRun(uint64_t seed, bool start_moving, double duration_s = 30)
{
    sim::GroundRobotOptions o;
    o.start_moving = start_moving;
    RobotRun r;
    r.layout = sim::makeFloorLayout(sim::FloorOptions{}, seed, "test");
    r.motion = sim::generateGroundRobotMotion(r.layout, o, duration_s, 100.0, seed, "test");
    return r;
}

/** On a door's passage: the straight line through the door between the corridor and the room. */
bool inDoorPassage(const sim::FloorLayout& l, const Eigen::Vector2d& p)
{
    for (const sim::FloorRoom& r : l.rooms)
        if (std::abs(p.x() - r.door_x) < 1e-6 && p.y() * r.side >= 0 &&
            std::abs(p.y()) <= l.corridor_half_width + 1.0 + 1e-6)
            return true;
    return false;
}
}  // namespace

TEST(RobotMotion, SpeedBoundsPlanarityStopsAndTurnsInPlace)
{
    const sim::GroundRobotOptions o;
    size_t total_waits = 0;
    for (uint64_t seed = 1; seed <= 5; ++seed)
    {
        const RobotRun run = makeRun(seed, false);
        const auto& planar = run.motion.planar;
        const auto& poses = run.motion.T_world_base.poses;
        ASSERT_EQ(planar.size(), poses.size());
        const double dt = 1.0 / o.sample_rate_hz;
        total_waits += run.motion.stops;
        double max_speed = 0, max_fd_speed = 0, max_z = 0, max_tilt = 0, stand_run = 0, longest_wait = 0;
        size_t turn_samples = 0;
        for (size_t i = 0; i < planar.size(); ++i)
        {
            const sim::PlanarState& s = planar[i];
            max_speed = std::max(max_speed, s.speed);
            if (i > 0)  // the poses themselves, not the profile: finite-difference speed
            {
                const double d =
                    std::hypot(poses[i].pose.x() - poses[i - 1].pose.x(), poses[i].pose.y() - poses[i - 1].pose.y());
                max_fd_speed = std::max(max_fd_speed, d / dt);
            }
            max_z = std::max(max_z, std::abs(poses[i].pose.z()));
            max_tilt =
                std::max({max_tilt, std::abs(double(poses[i].pose.pitch())), std::abs(double(poses[i].pose.roll()))});
            // A wait: the robot still for a while between the initial stand and the final one, then moving again.
            const bool still = s.speed == 0 && s.yaw_rate == 0;
            if (!still && stand_run > 0 && s.t - planar.front().t > o.standing_s + 0.1)
                longest_wait = std::max(longest_wait, stand_run);
            stand_run = still ? stand_run + dt : 0;
            if (s.speed == 0 && std::abs(s.yaw_rate) > 0.3) ++turn_samples;
            EXPECT_TRUE(run.layout.isFree(s.p, 0.3) || inDoorPassage(run.layout, s.p))
                << "seed " << seed << " at " << s.p.transpose();
        }
        // Speed: within the robot's bounds, and it does reach cruise speeds of the range.
        EXPECT_LE(max_speed, o.max_speed_m_s + 1e-9) << seed;
        EXPECT_LE(max_fd_speed, o.max_speed_m_s * 1.001) << seed;
        EXPECT_GE(max_speed, 0.8) << seed;
        // Planar: z and roll / pitch only from vibration (a few mm, well under a degree), but present.
        EXPECT_LT(max_z, 0.005) << seed;
        EXPECT_GT(max_z, 0.0005) << seed;
        EXPECT_LT(max_tilt, 1.0 * kDeg) << seed;
        EXPECT_GT(max_tilt, 0.1 * kDeg) << seed;
        // Stop-and-go: a stop at every waypoint, and waits of at least robot_stop_min_s where one was drawn;
        // turns in place (at zero speed).
        if (run.motion.stops > 0)
        {
            EXPECT_GE(longest_wait, o.stop_min_s - 1e-9) << seed;
        }
        EXPECT_GT(turn_samples, 100u) << seed;
        EXPECT_GE(run.motion.turns_in_place, 3u) << seed;
        EXPECT_GE(run.motion.rooms_visited, 1u) << seed;
        // Long enough: 30 s after the first frame.
        EXPECT_GE(poses.back().t - poses.front().t - run.motion.first_frame_offset_s, 30.0) << seed;
    }
    EXPECT_GE(total_waits, 3u);  // about a third of ~10 waypoints per tour
}

TEST(RobotMotion, StartsStandingOrMoving)
{
    const sim::GroundRobotOptions o;
    for (const bool moving : {false, true})
    {
        const RobotRun run = makeRun(3, moving);
        const double t_first = run.motion.planar.front().t + run.motion.first_frame_offset_s;
        const auto it = std::lower_bound(run.motion.planar.begin(), run.motion.planar.end(), t_first - 1e-9,
                                         [](const sim::PlanarState& s, double t) { return s.t < t; });
        ASSERT_NE(it, run.motion.planar.end());
        if (moving)
            EXPECT_GE(it->speed, o.min_speed_m_s);
        else
        {
            EXPECT_EQ(it->speed, 0.0);
            EXPECT_EQ(it->yaw_rate, 0.0);
        }
    }
}

TEST(RobotMotion, DeterministicPerSeed)
{
    const RobotRun a = makeRun(7, false), b = makeRun(7, false), c = makeRun(8, false);
    ASSERT_EQ(a.motion.T_world_base.poses.size(), b.motion.T_world_base.poses.size());
    for (size_t i = 0; i < a.motion.T_world_base.poses.size(); i += 97)
        EXPECT_EQ(a.motion.T_world_base.poses[i].pose, b.motion.T_world_base.poses[i].pose);
    EXPECT_NE(a.motion.waypoints, c.motion.waypoints);
}

TEST(RobotMotion, BadInputIsAnError)
{
    sim::GroundRobotOptions o;
    o.max_speed_m_s = 0.2;  // below min_speed_m_s
    EXPECT_THROW(sim::driveWaypoints({{0, 0}, {1, 0}}, o, 0, 1, "test"), core::InputError);
    EXPECT_THROW(sim::driveWaypoints({{0, 0}}, sim::GroundRobotOptions{}, 0, 1, "test"), core::InputError);
    sim::FloorOptions f;
    f.door_width_m = 4.5;  // wider than the narrowest room can hold
    EXPECT_THROW(sim::makeFloorLayout(f, 1, "test"), core::InputError);
}

TEST(FloorWorld, RoomsPartitionTheCorridorAndClutterKeepsClearOfThePath)
{
    const RobotRun run = makeRun(2, false);
    const sim::FloorLayout& l = run.layout;
    for (const int side : {1, -1})
    {
        double x = 0;
        for (const sim::FloorRoom& r : l.rooms)
            if (r.side == side)
            {
                EXPECT_NEAR(r.box.min().x(), x, 1e-9);
                EXPECT_GT(r.door_x - 0.5 * l.door_width, r.box.min().x());
                EXPECT_LT(r.door_x + 0.5 * l.door_width, r.box.max().x());
                x = r.box.max().x();
            }
        EXPECT_NEAR(x, l.corridor_length, 1e-9);
    }
    EXPECT_GE(l.rooms.size(), 6u);
    std::vector<Eigen::Vector3f> path;
    const mrpt::poses::CPose3D T_base_cam = sim::baseToCamera(sim::GroundRobotOptions{});
    for (size_t i = 0; i < run.motion.T_world_base.poses.size(); i += 10)
    {
        const mrpt::poses::CPose3D T = run.motion.T_world_base.poses[i].pose + T_base_cam;
        path.emplace_back(float(T.x()), float(T.y()), float(T.z()));
    }
    sim::WorldOptions o;
    o.world = sim::ViconRoom::office_floor;
    o.clearance_m = 0.5;
    o.shadow_map_px = 0;
    o.texture_size_px = 64;
    sim::WorldStats st;
    const sim::World w = sim::buildFloorWorld(o, l, 2, path, &st);
    EXPECT_GT(st.objects_placed, l.rooms.size() * 2);
    EXPECT_EQ(w.lights.size(), 2 * l.rooms.size() + 6);
    for (const auto& p : path) EXPECT_TRUE(w.room.contains(p));
    // Nothing closer to the camera than the floor below it (0.45 m): the clutter keeps its 0.5 m, the door
    // frames are 0.7 m to the side.
    EXPECT_GE(st.min_clearance_m, 0.44);
}

TEST(ImuBiasDraw, RandomDrawIsNeverZeroAndWithinTheBounds)
{
    std::set<double> distinct;
    for (uint64_t seed = 1; seed <= 20; ++seed)
    {
        sim::ImuNoiseOptions o;
        o.seed = seed;
        sim::drawInitialBiases(o);
        for (int i = 0; i < 3; ++i)
        {
            EXPECT_GE(std::abs(o.initial_gyro_bias[i]), 0.3 * o.gyro_bias_max_rad_s - 1e-12);
            EXPECT_LE(std::abs(o.initial_gyro_bias[i]), o.gyro_bias_max_rad_s + 1e-12);
            EXPECT_GE(std::abs(o.initial_acc_bias[i]), 0.3 * o.acc_bias_max_m_s2 - 1e-12);
            EXPECT_LE(std::abs(o.initial_acc_bias[i]), o.acc_bias_max_m_s2 + 1e-12);
        }
        distinct.insert(o.initial_gyro_bias.x());
    }
    EXPECT_EQ(distinct.size(), 20u);
}

TEST(AutoExposure, StepsBetweenDiscreteLevels)
{
    sim::AppearanceOptions o;
    o.exposure_variation = 0.25;
    o.exposure_period_s = 9;
    o.auto_exposure_step = 0.08;
    o.auto_exposure_interval_s = 0.5;
    std::set<long> levels;
    size_t changes = 0;
    double last = sim::exposureAt(o, 4, 0);
    for (double t = 0; t < 20; t += 1.0 / 30)
    {
        const double e = sim::exposureAt(o, 4, t);
        const double k = std::log(e / o.exposure) / std::log1p(o.auto_exposure_step);
        EXPECT_NEAR(k, std::round(k), 1e-9);  // on a level exposure x 1.08^k
        levels.insert(std::lround(k));
        if (e != last)
        {
            ++changes;
            EXPECT_NEAR(std::fmod(t + 1e-9, o.auto_exposure_interval_s), 0.0, 1.0 / 30 + 1e-6);  // at an update
        }
        last = e;
    }
    EXPECT_GE(levels.size(), 5u);
    EXPECT_GE(changes, 8u);
    o.auto_exposure_step = 0;  // continuous: changes every frame
    EXPECT_NE(sim::exposureAt(o, 4, 1.0), sim::exposureAt(o, 4, 1.0 + 1.0 / 30));
}
