// The keys of [Simulation] and [IMU], each declared once (name, member, unit, range, meaning), and the checks that a
// range cannot say.
#include <quasiloc/core/error.h>
#include <quasiloc/sim/simulation.h>

namespace quasiloc::sim
{
using core::Range;

namespace
{
std::string sourceName(ImuSource s) { return s == ImuSource::real ? "real" : "synthetic"; }
std::string biasName(ImuBiasModel b)
{
    return b == ImuBiasModel::random_walk   ? "random_walk"
           : b == ImuBiasModel::random_draw ? "random_draw"
                                            : "euroc_groundtruth";
}
}  // namespace

void SimulationOptions::declare(core::OptionTable& t)
{
    t.add("output_dir", output_dir, "the folder written (required); it appears complete or not at all");
    t.add("sequence", sequence, "name of the rawlog and of the default trajectory");
    t.add("shared_dir", shared_dir, "the shared data folder (EuRoC calibration, ground truth, room maps)");
    t.add("trajectory", trajectory,
          "TUM of T_world_cam0; empty = <shared_dir>/data/euroc/groundtruth/cam0/<sequence>.txt");
    t.add("duration_s", duration_s, "s", Range::atLeast(0), "span of the camera frames; 0 = the whole trajectory");
    t.add("start_offset_s", start_offset_s, "s", Range::atLeast(0), "first camera frame after the trajectory's start");
    t.add("camera_rate_hz", camera_rate_hz, "Hz", Range{0, 1000, true, false}, "stereo frame rate");
    t.add("seed", seed, "", Range::any(),
          "drives world, textures, LiDAR and image noise; the IMU's seed is [IMU] seed combined with it");
    t.add("cam0_yaml", cam0_yaml,
          "EuRoC sensor.yaml of the left camera; empty = <shared_dir>/data/euroc/calib/cam0_sensor.yaml");
    t.add("cam1_yaml", cam1_yaml,
          "EuRoC sensor.yaml of the right camera; empty = <shared_dir>/data/euroc/calib/cam1_sensor.yaml");
    t.add("camchain", camchain,
          "a Kalibr camchain YAML of the stereo rig (cam0 = left; T_cam_imu gives the body = IMU frame), instead of "
          "cam0_yaml / cam1_yaml (share/quasiloc/sim/d435i_camchain.yaml: a RealSense D435i)");
    t.addEnum("motion", motion,
              {{"trajectory", MotionSource::trajectory},
               {"ground_robot", MotionSource::ground_robot},
               {"car", MotionSource::car}},
              "trajectory: along `trajectory` (or EuRoC's ground truth); ground_robot: a ground robot's tour of the "
              "office floor generated from seed (robot_motion.h, keys robot_*; needs [World] world = floor); car: a "
              "car's route along the campus streets generated from seed (car_motion.h, keys car_*; needs [World] "
              "world = campus)");
    t.add("robot_min_speed_m_s", robot.min_speed_m_s, "m/s", Range::between(0.05, 5),
          "ground_robot: lowest cruise speed of a segment");
    t.add("robot_max_speed_m_s", robot.max_speed_m_s, "m/s", Range::between(0.05, 5),
          "ground_robot: highest cruise speed (>= robot_min_speed_m_s)");
    t.add("robot_max_accel_m_s2", robot.max_accel_m_s2, "m/s^2", Range::between(0.05, 10),
          "ground_robot: peak acceleration of the speed ramps");
    t.add("robot_max_yaw_rate_deg_s", robot.max_yaw_rate_deg_s, "deg/s", Range::between(5, 360),
          "ground_robot: peak yaw rate of a turn in place");
    t.add("robot_stop_probability", robot.stop_probability, "", Range::between(0, 1),
          "ground_robot: chance of a wait at a waypoint");
    t.add("robot_stop_min_s", robot.stop_min_s, "s", Range::between(0, 60), "ground_robot: shortest wait");
    t.add("robot_stop_max_s", robot.stop_max_s, "s", Range::between(0, 60), "ground_robot: longest wait");
    t.add("robot_standing_s", robot.standing_s, "s", Range::between(0.5, 60),
          "ground_robot: the robot stands still this long at the start");
    t.add("robot_start_moving", robot.start_moving,
          "ground_robot: the first frame when the first segment reaches its cruise speed; false: 0.5 s into the "
          "initial wait (start standing)");
    t.add("robot_start_in_corridor", robot.start_in_corridor,
          "ground_robot: start at the corridor's end looking along it (a view alike all along the corridor); "
          "false: near the far wall of a room, heading for its door");
    t.add("robot_camera_height_m", robot.camera_height_m, "m", Range::between(0.05, 3),
          "ground_robot: cam0 above the floor (looking horizontally forward)");
    t.add("robot_camera_forward_m", robot.camera_forward_m, "m", Range::between(-2, 2),
          "ground_robot: cam0 ahead of the rotation centre");
    t.add("robot_vibration_z_mm", robot.vibration_z_mm, "mm", Range::between(0, 50),
          "ground_robot: floor bounce, largest term (1.5-2.5 Hz) at full speed or yaw rate");
    t.add("robot_vibration_tilt_deg", robot.vibration_tilt_deg, "deg", Range::between(0, 10),
          "ground_robot: roll / pitch vibration, largest term (2-3 Hz) at full speed or yaw rate");
    t.add("robot_pitch_per_accel_deg", robot.pitch_per_accel_deg, "deg/(m/s^2)", Range::between(0, 10),
          "ground_robot: the body's pitch while accelerating");
    t.add("car_max_speed_m_s", car.max_speed_m_s, "m/s", Range::between(0.5, 40), "car: top speed on a straight");
    t.add("car_turn_speed_m_s", car.turn_speed_m_s, "m/s", Range::between(0.5, 20), "car: top speed on a turn's arc");
    t.add("car_max_accel_m_s2", car.max_accel_m_s2, "m/s^2", Range::between(0.1, 10),
          "car: largest acceleration and deceleration of the speed profile");
    t.add("car_turn_radius_m", car.turn_radius_m, "m", Range::between(2, 50),
          "car: radius of the arcs that round the lane's corners at intersections");
    t.add("car_lane_offset_m", car.lane_offset_m, "m", Range::between(0, 10),
          "car: the driving lane's centre, right of the street's centreline");
    t.add("car_stop_probability", car.stop_probability, "", Range::between(0, 1),
          "car: chance of a stop before an intersection's zebra crossing");
    t.add("car_stop_min_s", car.stop_min_s, "s", Range::between(0, 60), "car: shortest stop");
    t.add("car_stop_max_s", car.stop_max_s, "s", Range::between(0, 60), "car: longest stop");
    t.add("car_standing_s", car.standing_s, "s", Range::between(0.5, 60),
          "car: the car stands still this long at the start and at the end (the first frame 0.5 s into the start)");
    t.add("car_route_length_m", car.route_length_m, "m", Range::between(10, 1e5),
          "car: the route's length along the streets (whole streets: the last one may exceed it)");
    t.add("car_camera_height_m", car.camera_height_m, "m", Range::between(0.3, 4),
          "car: cam0 above the road (looking horizontally forward)");
    t.add("car_camera_forward_m", car.camera_forward_m, "m", Range::between(-3, 5),
          "car: cam0 ahead of the base origin (the rear axle)");
    t.add("car_pitch_per_accel_deg", car.pitch_per_accel_deg, "deg/(m/s^2)", Range::between(0, 10),
          "car: the body's pitch while accelerating or braking");
    t.add("car_roll_per_lateral_accel_deg", car.roll_per_lateral_accel_deg, "deg/(m/s^2)", Range::between(0, 10),
          "car: the body's roll in turns");
    t.add("spline_knot_spacing_s", spline_knot_spacing_s, "s", Range::between(0.005, 2),
          "knot spacing of the spline fitted to the trajectory");
    t.add("write_map", write_map, "write lidar_map.map (and the 32-beam map with [Lidar] beam_map)");
    t.add("write_map_materials", write_map_materials,
          "with write_map: also lidar_map_materials.bin, the material of every survey map point (material_labels.h)");
    t.add("inspection_png", inspection_png,
          "write inspection.png (needs the LiDAR map, sampled even without write_map)");
    t.add("verbose", verbose, "progress on stdout");
}

void SimulationOptions::check(const std::string& in) const
{
    checkRanges(in);
    core::require(!output_dir.empty(), in + " output_dir", "is required");
    core::require(!sequence.empty() && sequence.find('/') == std::string::npos, in + " sequence",
                  "must be a plain name (it names the rawlog)");
    core::require(camchain.empty() || (cam0_yaml.empty() && cam1_yaml.empty()), in + " camchain",
                  "is an alternative to cam0_yaml / cam1_yaml: give one or the other");
    core::require(robot.max_speed_m_s >= robot.min_speed_m_s, in + " robot_max_speed_m_s",
                  "must be >= robot_min_speed_m_s");
    core::require(robot.stop_max_s >= robot.stop_min_s, in + " robot_stop_max_s", "must be >= robot_stop_min_s");
    core::require(motion == MotionSource::trajectory || trajectory.empty(), in + " trajectory",
                  "is not read with motion = ground_robot or car");
    core::require(car.stop_max_s >= car.stop_min_s, in + " car_stop_max_s", "must be >= car_stop_min_s");
}

void ImuNoiseOptions::declare(core::OptionTable& t)
{
    t.addEnum("source", source, {{"synthetic", ImuSource::synthetic}, {"real", ImuSource::real}},
              "synthetic: samples synthesized on the spline; real: a real EuRoC imu0/data.csv replayed "
              "(imu_synthesizer.h)");
    t.add("real_imu_csv", real_imu_csv,
          "source = real only; empty = <shared_dir>/data/euroc/V1_01_easy_micro/mav0/imu0/data.csv");
    t.add("rate_hz", rate_hz, "Hz", Range::above(0), "sample rate (source = real: the file's nominal rate, gap check)");
    t.add("gyroscope_noise_density", gyroscope_noise_density, "rad/s/sqrt(Hz)", Range::atLeast(0), "white noise");
    t.add("gyroscope_random_walk", gyroscope_random_walk, "rad/s^2/sqrt(Hz)", Range::atLeast(0), "bias random walk");
    t.add("accelerometer_noise_density", accelerometer_noise_density, "m/s^2/sqrt(Hz)", Range::atLeast(0),
          "white noise");
    t.add("accelerometer_random_walk", accelerometer_random_walk, "m/s^3/sqrt(Hz)", Range::atLeast(0),
          "bias random walk");
    t.add("gravity_m_s2", gravity_m_s2, "m/s^2", Range::atLeast(0), "magnitude of gravity (along -z of the world)");
    t.add("noise_enabled", noise_enabled, "white noise and bias random walk; false = exact samples plus the biases");
    t.add("seed", seed, "", Range::any(), "noise seed, combined with [Simulation] seed");
    t.addEnum("bias", bias,
              {{"euroc_groundtruth", ImuBiasModel::euroc_groundtruth},
               {"random_walk", ImuBiasModel::random_walk},
               {"random_draw", ImuBiasModel::random_draw}},
              "euroc_groundtruth: EuRoC's ground-truth bias trajectory where there is one, else the random walk; "
              "random_walk: from the initial biases; random_draw: from initial biases drawn from the seed (each axis "
              "0.3..1 x gyro_bias_max_rad_s / acc_bias_max_m_s2, random sign)");
    t.add("bias_file", bias_file,
          "bias = euroc_groundtruth only; empty = <shared_dir>/data/euroc/groundtruth/body/<sequence>.csv "
          "if it exists");
    t.add("initial_gyro_bias", initial_gyro_bias, "rad/s", Range::any(), "start of the random walk (EuRoC's biases)");
    t.add("initial_acc_bias", initial_acc_bias, "m/s^2", Range::any(), "start of the random walk (EuRoC's biases)");
    t.add("gyro_bias_max_rad_s", gyro_bias_max_rad_s, "rad/s", Range::between(1e-6, 1),
          "bias = random_draw: bound of each axis' drawn gyroscope bias");
    t.add("acc_bias_max_m_s2", acc_bias_max_m_s2, "m/s^2", Range::between(1e-6, 5),
          "bias = random_draw: bound of each axis' drawn accelerometer bias");
    t.add("kalibr_yaml", kalibr_yaml,
          "a Kalibr imu.yaml: rate_hz and the four noise densities are taken from it (share/quasiloc/sim/"
          "d435i_imu.yaml: the D435i's BMI055)");
}

void ImuNoiseOptions::check(const std::string& in) const
{
    checkRanges(in);
    core::require(real_imu_csv.empty() || source == ImuSource::real, in + " real_imu_csv",
                  "is read only with source = real (got source = " + sourceName(source) + ")");
    core::require(bias_file.empty() || bias == ImuBiasModel::euroc_groundtruth, in + " bias_file",
                  "is read only with bias = euroc_groundtruth (got bias = " + biasName(bias) + ")");
}

}  // namespace quasiloc::sim
