#pragma once
// A car driving through the campus (campus_world.h), generated from a seed: a route along the streets with turns at
// intersections and stops before some of them, driven with a speed profile bounded by the options.
//
// Route: from a random intersection, street by street: at each intersection straight on (half the time) or a turn
// left or right, never back, until the route is route_length_m long; the car keeps to the right-hand lane
// (lane_offset_m right of the centreline).
// Driving (decisions):
// - the corners of the lane are rounded to arcs of turn_radius_m; on an arc the speed is at most turn_speed_m_s;
// - at an intersection the car stops before the zebra crossing with stop_probability and waits stop_min_s..stop_max_s;
// - the speed profile is the fastest under max_speed_m_s and those limits with accelerations of at most
//   max_accel_m_s2 (forward and backward passes on a 5 cm grid of the path), constant acceleration between grid points;
// - the base pose is planar (x, y, yaw) with the body's pitch while accelerating (pitch_per_accel_deg) and its roll in
//   turns (roll_per_lateral_accel_deg): no road vibration;
// - the car stands still standing_s at the start and the end; the first frame is half a second into the start.
#include <Eigen/Core>
#include <cstdint>
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/sim/campus_world.h>
#include <string>
#include <vector>

namespace quasiloc::sim
{
/** Keys car_* of [Simulation] (sequence_options.cpp). */
struct CarOptions
{
    double max_speed_m_s = 10;
    double turn_speed_m_s = 4;
    double max_accel_m_s2 = 1.5;
    double turn_radius_m = 7;
    double lane_offset_m = 2;
    double stop_probability = 0.3;
    double stop_min_s = 1, stop_max_s = 4;
    double standing_s = 2;
    double route_length_m = 1500;
    double camera_height_m = 1.65;  ///< of cam0 above the road (KITTI's)
    double camera_forward_m = 1.0;  ///< of cam0 ahead of the base origin (the rear axle)
    double pitch_per_accel_deg = 0.3;
    double roll_per_lateral_accel_deg = 0.3;
    double sample_rate_hz = 200;
};

struct CarMotion
{
    core::Trajectory T_world_base;               ///< base frame: x forward, y left, z up; origin on the road
    std::vector<Eigen::Vector2d> intersections;  ///< the route's nodes, centreline coordinates
    double first_frame_offset_s = 0;             ///< the first camera frame, after the motion's start
    size_t stops = 0, turns = 0;
    double length_m = 0, duration_s = 0, top_speed_m_s = 0;
};

/** The route's intersections: at least options.route_length_m along the centrelines. */
std::vector<Eigen::Vector2d> planCarRoute(const CampusLayout& layout, const CarOptions& options, uint64_t seed);

/** Drives the route (lane, arcs, stops, speed profile), sampled at options.sample_rate_hz from t0. InputError naming
 *  `input` for options out of range or a turn radius the blocks cannot hold. */
CarMotion driveCarRoute(const CampusLayout& layout, const std::vector<Eigen::Vector2d>& intersections,
                        const CarOptions& options, double t0, uint64_t seed, const std::string& input);

/** T_base_cam0 of the forward-looking camera (optical axes: z forward, x right, y down) at the options' mount. */
mrpt::poses::CPose3D carBaseToCamera(const CarOptions& options);

}  // namespace quasiloc::sim
