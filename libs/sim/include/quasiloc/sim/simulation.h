#pragma once
// sim-rawlog as a library call: one simulated EuRoC-like sequence written into [Simulation] output_dir:
//   lidar_map.map            the survey LiDAR map (map::LidarMap file), [+ lidar_map_32beam.map]
//   [lidar_map_materials.bin the material of every survey map point (material_labels.h), with write_map_materials]
//   <sequence>.rawlog        stereo observations at camera_rate_hz and IMU observations, in time order
//   <sequence>_Images/       the raw (distorted) 8-bit PNG images
//   gt.tum                   T_world_cam0 at every camera frame
//   gt_body.tum              T_world_body (IMU frame) at every IMU sample
//   gt_imu_bias.csv          the true biases of every IMU sample: "t [s], b_g xyz [rad/s], b_a xyz [m/s^2]";
//                            not written for [IMU] source = real (the real sensor's biases are unknown)
//   calib.ini                stereo rig (core::StereoRig INI, prefix camera_) and [imu] noise model (rate,
//                            densities, gravity: what a calibration gives; no simulation keys, no true biases)
//   sim-rawlog.ini           the effective configuration
//   inspection.png           a camera frame beside the map's reflectivity projected at the same pose
//   README.txt               what the folder holds
// Everything is staged (core::StagedOutputs): the folder appears complete or not at all.
//
// Decisions: relative paths in the INI are relative to the working directory; the trajectory defaults to
// <shared_dir>/data/euroc/groundtruth/cam0/<sequence>.txt; the spline is fitted to it (simimu's
// TrajectorySpline), camera frames start at tStart() + start_offset_s; IMU samples are generated on the
// spline from the first to the last camera frame, or with [IMU] source = real the real samples of that span
// (imu_synthesizer.h). The spline keeps the trajectory's timestamps: EuRoC ground truth is on the EuRoC clock
// (seconds since 1970), the clock of the ground-truth bias files and of the real imu0/data.csv. The world keeps clear
// of every ground-truth trajectory of its room and of the simulated one. Seeds: Simulation.seed drives world, textures,
// LiDAR and image noise; the IMU's seed is [IMU] seed combined with Simulation.seed.
#include <mrpt/config/CConfigFileBase.h>

#include <quasiloc/core/declared_options.h>
#include <quasiloc/sim/car_motion.h>
#include <quasiloc/sim/imu_synthesizer.h>
#include <quasiloc/sim/lidar_sampler.h>
#include <quasiloc/sim/robot_motion.h>
#include <quasiloc/sim/stereo_renderer.h>
#include <quasiloc/sim/world_builder.h>
#include <string>

namespace quasiloc::sim
{
/** How the rig moves: along a given trajectory (EuRoC's ground truth or `trajectory`), as a ground robot
 *  through the office floor (robot_motion.h; needs [World] world = floor), or as a car through the campus
 *  (car_motion.h; needs [World] world = campus). */
enum class MotionSource
{
    trajectory,
    ground_robot,
    car
};

/** Section [Simulation]; each key's unit, range and meaning: declare() (sequence_options.cpp). */
struct SimulationOptions : public core::DeclaredOptions
{
    std::string output_dir;
    std::string sequence = "V1_01_easy";
    std::string shared_dir = "../shared";
    std::string trajectory;
    double duration_s = 0;
    double start_offset_s = 0;
    double camera_rate_hz = 20;
    uint64_t seed = 1;
    std::string cam0_yaml, cam1_yaml;
    std::string camchain;  ///< a Kalibr camchain instead of cam0_yaml / cam1_yaml
    MotionSource motion = MotionSource::trajectory;
    GroundRobotOptions robot;  ///< motion = ground_robot (keys robot_*)
    CarOptions car;            ///< motion = car (keys car_*)
    double spline_knot_spacing_s = 0.1;
    bool write_map = true;
    bool write_map_materials = false;
    bool inspection_png = true;
    bool verbose = true;

    void declare(core::OptionTable& t) override;
    /** The declared ranges, output_dir given, sequence a plain name (InputError naming `input` and the key). */
    void check(const std::string& input) const;
};

struct SimulationResult
{
    size_t frames = 0, imu_samples = 0, map_points = 0, beam_map_points = 0;
    std::string imu_description;    ///< IMU source and bias model, one line
    bool imu_bias_written = false;  ///< gt_imu_bias.csv (not for source = real)
    WorldStats world;
    double world_time_s = 0, map_time_s = 0, render_time_s = 0, total_time_s = 0;
    double mean_render_ms = 0, max_render_ms = 0;  ///< per stereo frame
    std::vector<std::string> files;                ///< final paths written
};

/** Runs the simulation from a merged configuration (sections Simulation, World, Appearance, Lidar, IMU;
 *  unknown keys are errors). `config_name` names the configuration in error messages. With print_timing, the
 *  per-stage CTimeLogger table is printed at the end (by the logger's destructor). */
SimulationResult runSimulation(const mrpt::config::CConfigFileBase& cfg, const std::string& config_name,
                               bool print_timing = false);

}  // namespace quasiloc::sim
