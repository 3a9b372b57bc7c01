#pragma once
// A ground robot's motion through the office floor (floor_world.h), generated from a seed: a tour of waypoints
// through the floor's free space, driven as a differential-drive robot does it, plus floor vibration.
//
// Tour: from near the far wall of a room (or with start_in_corridor from the corridor's west end, looking along it: a
// view the same at every place of the corridor, so global localization cannot tell where it is) out through its door
// and along the corridor; some rooms are entered through their door, one or two points inside are visited, and the
// robot leaves the same way; at the corridor's end it turns around. The tour grows until it lasts min_duration_s.
// Driving (decisions):
// - at every waypoint the robot stops and turns in place to the next heading (a raised-cosine yaw profile, peak
//   rate max_yaw_rate_deg_s at most); sometimes it also waits (stop_probability, stop_min_s..stop_max_s);
// - each straight segment has a cruise speed drawn in [min_speed_m_s, max_speed_m_s], reached and left by
//   raised-cosine speed ramps of peak acceleration max_accel_m_s2; a segment too short for its ramps peaks lower;
// - the base pose is planar (x, y, yaw); the floor adds vertical bounce (z) and roll/pitch vibration, sums of
//   sinusoids at 1.5-8 Hz scaled by how hard the robot moves (speed or yaw rate against their maxima), plus a
//   pitch of pitch_per_accel_deg per m/s^2 while accelerating (the body rocking on its suspension).
// The robot stands still for standing_s at the start. Two starts of a sequence: standing (the first frame half a
// second into that wait) or moving (the first frame when the first segment reaches its cruise speed).
#include <Eigen/Core>
#include <cstdint>
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/sim/floor_world.h>
#include <string>
#include <vector>

namespace quasiloc::sim
{
/** Keys robot_* of [Simulation] (sim_options.cpp). */
struct GroundRobotOptions
{
    double min_speed_m_s = 0.3;
    double max_speed_m_s = 1.5;
    double max_accel_m_s2 = 0.6;
    double max_yaw_rate_deg_s = 60;
    double stop_probability = 0.35;
    double stop_min_s = 0.5, stop_max_s = 2.5;
    double standing_s = 2.0;
    bool start_moving = false;
    bool start_in_corridor = false;   ///< the tour starts at the corridor's west end instead of inside a room
    double camera_height_m = 0.45;    ///< of cam0 above the floor
    double camera_forward_m = 0.20;   ///< of cam0 ahead of the rotation centre
    double vibration_z_mm = 2.0;      ///< amplitude of the largest bounce term at full effort
    double vibration_tilt_deg = 0.3;  ///< amplitude of the largest roll / pitch term at full effort
    double pitch_per_accel_deg = 0.3;
    double sample_rate_hz = 200;  ///< of the generated poses
};

/** Planar state of the base (before vibration) at one sample. */
struct PlanarState
{
    double t = 0;
    Eigen::Vector2d p = Eigen::Vector2d::Zero();
    double yaw = 0, speed = 0, yaw_rate = 0, accel = 0;
};

struct GroundRobotMotion
{
    core::Trajectory T_world_base;  ///< base frame: x forward, y left, z up; origin on the floor at the rotation centre
    std::vector<PlanarState> planar;  ///< parallel to T_world_base.poses
    std::vector<Eigen::Vector2d> waypoints;
    double first_frame_offset_s = 0;  ///< the first camera frame, after the motion's start
    size_t stops = 0, turns_in_place = 0, rooms_visited = 0;
    double length_m = 0;
};

/** The waypoints of a tour lasting at least min_duration_s (estimated from the options). */
std::vector<Eigen::Vector2d> planFloorTour(const FloorLayout& layout, const GroundRobotOptions& options,
                                           double min_duration_s, uint64_t seed);

/** Drives `waypoints` (first = start, heading towards the second) and adds the vibration; samples at
 *  options.sample_rate_hz from t0. InputError naming `input` for fewer than two waypoints or options out of range. */
GroundRobotMotion driveWaypoints(const std::vector<Eigen::Vector2d>& waypoints, const GroundRobotOptions& options,
                                 double t0, uint64_t seed, const std::string& input);

/** T_base_cam0 of a forward-looking camera (optical axes: z forward, x right, y down) at the options' mount. */
mrpt::poses::CPose3D baseToCamera(const GroundRobotOptions& options);

/** The whole motion: tour (at least min_duration_s after the first frame) then drive. */
GroundRobotMotion generateGroundRobotMotion(const FloorLayout& layout, const GroundRobotOptions& options,
                                            double min_duration_s, double t0, uint64_t seed, const std::string& input);

}  // namespace quasiloc::sim
