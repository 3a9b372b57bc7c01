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
std::string biasName(ImuBiasModel b) { return b == ImuBiasModel::random_walk ? "random_walk" : "euroc_groundtruth"; }
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
    t.add("spline_knot_spacing_s", spline_knot_spacing_s, "s", Range::between(0.005, 2),
          "knot spacing of the spline fitted to the trajectory");
    t.add("write_map", write_map, "write lidar_map.map (and the 32-beam map with [Lidar] beam_map)");
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
              {{"euroc_groundtruth", ImuBiasModel::euroc_groundtruth}, {"random_walk", ImuBiasModel::random_walk}},
              "euroc_groundtruth: EuRoC's ground-truth bias trajectory where there is one, else the random walk; "
              "random_walk: from the initial biases");
    t.add("bias_file", bias_file,
          "bias = euroc_groundtruth only; empty = <shared_dir>/data/euroc/groundtruth/body/<sequence>.csv "
          "if it exists");
    t.add("initial_gyro_bias", initial_gyro_bias, "rad/s", Range::any(), "start of the random walk (EuRoC's biases)");
    t.add("initial_acc_bias", initial_acc_bias, "m/s^2", Range::any(), "start of the random walk (EuRoC's biases)");
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
