#pragma once
// IMU synthesis from a TrajectorySpline: specific force f = R_world_body^T (a_world - g_world) and angular
// rate omega_body, plus discrete-time white noise and biases with continuous-time densities
// (Kalibr/EuRoC convention: sigma_discrete = density / sqrt(dt) for white noise,
// bias step sigma = random_walk * sqrt(dt)). Deterministic for a seed.
//
// Biases, two models:
//  - a bias trajectory (ImuBiasTrajectory, e.g. EuRoC's ground truth): sample k carries the trajectory's
//    biases interpolated at t_k (linear; before the first / after the last row the first / last value is held);
//    white noise is added on top, no random walk.
//  - otherwise a random walk: sample k carries b_k, b_0 = initial_*_bias,
//    b_{k+1} = b_k + N(0, (random_walk sqrt(dt))^2).
// With noise_enabled = false the samples are exact plus the biases: those of the trajectory, or the constant
// initial biases (no random walk).
//
// How the simulation (simulation.h) uses [IMU] (keys: ImuNoiseOptions::declare, sim_options.cpp):
//  - source = real replays a real EuRoC imu0/data.csv unchanged in the span of the simulated frames, on the
//    ground-truth clock (a semi-real sequence: real IMU, rendered images; frame times within 1 us of an IMU tick
//    move onto it, snapToImuTicks). Only V1_01_easy's IMU file is available, and the file must cover the frames.
//    The biases of such a sequence are unknown (V1_01 has no ground-truth body csv), so no noise, bias or seed
//    key is used.
//  - bias = euroc_groundtruth follows the b_w, b_a columns of a state_groundtruth_estimate0/data.csv: bias_file,
//    else <shared_dir>/data/euroc/groundtruth/body/<sequence>.csv where it exists (V1_02, V1_03, V2_01, V2_02,
//    V2_03), else (V1_01_easy, own trajectories) the random walk. The file's clock must overlap the simulated one.
//  - the initial biases default to EuRoC's real ones (V2_01_easy's ground truth), about the same in every
//    sequence (docs/experiments.md).
// ImuSynthesizer itself reads neither source nor bias/bias_file: the simulation resolves them
// (resolveImuBias, selectRealImu) and hands the synthesizer a bias trajectory or none.
#include <optional>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/dataset/euroc_imu_csv.h>
#include <quasiloc/dataset/frame.h>
#include <quasiloc/sim/trajectory_spline.h>
#include <random>
#include <string>
#include <vector>

namespace quasiloc::sim
{
enum class ImuSource
{
    synthetic,
    real
};

enum class ImuBiasModel
{
    euroc_groundtruth,
    random_walk,
    random_draw  ///< the random walk from initial biases drawn from the seed (drawInitialBiases)
};

/** Section [IMU]; each key's unit, range and meaning: declare() (sim_options.cpp). */
struct ImuNoiseOptions : public core::DeclaredOptions
{
    ImuSource source = ImuSource::synthetic;
    std::string real_imu_csv;
    double rate_hz = 200;
    double gyroscope_noise_density = 1.6968e-04;
    double gyroscope_random_walk = 1.9393e-05;
    double accelerometer_noise_density = 2.0000e-3;
    double accelerometer_random_walk = 3.0000e-3;
    double gravity_m_s2 = 9.81;
    bool noise_enabled = true;
    uint64_t seed = 1;
    ImuBiasModel bias = ImuBiasModel::euroc_groundtruth;
    std::string bias_file;
    Eigen::Vector3d initial_gyro_bias{-0.0023, 0.0249, 0.0817};  ///< EuRoC's (header comment)
    Eigen::Vector3d initial_acc_bias{-0.021, 0.122, 0.079};      ///< EuRoC's (header comment)
    double gyro_bias_max_rad_s = 0.00873;  ///< bias = random_draw: per-axis magnitude bound (0.5 deg/s)
    double acc_bias_max_m_s2 = 0.08;       ///< bias = random_draw: per-axis magnitude bound
    std::string kalibr_yaml;               ///< a Kalibr imu.yaml: rate and the four densities from it

    void declare(core::OptionTable& t) override;
    /** The declared ranges; real_imu_csv only with source = real, bias_file only with bias = euroc_groundtruth. */
    void check(const std::string& input) const;
    /** Densities from an EuRoC/Kalibr imu sensor.yaml (rate_hz too). */
    void loadFromEurocYaml(const std::string& path);
};

/** True biases over time: linear interpolation between rows; the first / last row's value is held before /
 *  after the rows' time span. */
class ImuBiasTrajectory
{
   public:
    /** InputError naming `source` when empty, of different lengths, not strictly increasing in time or not finite. */
    ImuBiasTrajectory(std::vector<double> t, std::vector<Eigen::Vector3d> gyro_bias,
                      std::vector<Eigen::Vector3d> acc_bias, std::string source);
    /** The ground-truth biases of a EuRoC state csv (dataset::readEurocBiasCsv). */
    static ImuBiasTrajectory fromEuroc(const dataset::EurocBiasCsv& csv);

    void at(double t, Eigen::Vector3d& gyro_bias, Eigen::Vector3d& acc_bias) const;
    double tStart() const { return t_.front(); }
    double tEnd() const { return t_.back(); }
    const std::string& source() const { return source_; }

   private:
    std::vector<double> t_;
    std::vector<Eigen::Vector3d> gyro_, acc_;
    std::string source_;
};

/** bias = random_draw: sets options.initial_gyro_bias / initial_acc_bias to biases drawn from options.seed, each axis
 *  of magnitude uniform in [0.3, 1] x its bound with a random sign (a consumer MEMS part's turn-on bias: never zero,
 *  up to the bound). */
void drawInitialBiases(ImuNoiseOptions& options);

/** The bias model a simulation uses, resolved from [IMU] bias / bias_file (header comment). */
struct ResolvedImuBias
{
    std::optional<ImuBiasTrajectory> trajectory;  ///< empty = random walk from the initial biases
    std::string description;                      ///< one line for logs and README
};

/** `t0_s`, `t1_s`: the simulated IMU span; a bias file that does not overlap it is an InputError (another
 *  clock). `input` names the configuration in errors. */
ResolvedImuBias resolveImuBias(const ImuNoiseOptions& options, const std::string& shared_dir,
                               const std::string& sequence, double t0_s, double t1_s, const std::string& input);

/** source = real: the rows of `real` with t0_ns <= t_ns <= t1_ns, unchanged. InputError naming real.path when
 *  the file does not cover [t0_ns, t1_ns] (to within one nominal period at `rate_hz`). */
dataset::EurocImuCsv selectRealImu(const dataset::EurocImuCsv& real, std::int64_t t0_ns, std::int64_t t1_ns,
                                   double rate_hz);

/** source = real: EuRoC's camera and IMU share clock ticks, but a frame time taken from the ground truth's decimal
 *  seconds is off its tick by up to ~130 ns. Moves each of `t_ns` that lies within `tolerance_ns` of a tick of
 *  `imu_t_ns` (sorted) onto it, so the IMU sample of a frame's instant belongs to that frame. Returns how many moved.
 */
size_t snapToImuTicks(std::vector<std::int64_t>& t_ns, const std::vector<std::int64_t>& imu_t_ns,
                      std::int64_t tolerance_ns = 1000);

/** One synthesized sample with the true biases that were added (for tests and evaluation). */
struct ImuTruth
{
    double t = 0;
    Eigen::Vector3d gyro_bias, acc_bias;
};

class ImuSynthesizer
{
   public:
    /** The body frame of the spline is the IMU frame. InputError when options.check() fails. With `biases`,
     *  the biases follow it; without, the random walk from the initial biases. */
    ImuSynthesizer(const TrajectorySpline& spline, const ImuNoiseOptions& options,
                   std::optional<ImuBiasTrajectory> biases = std::nullopt);
    /** Samples at t0, t0 + 1/rate, ... <= t1 (t0, t1 within the spline, else std::out_of_range). Continues the bias
     * random walk across calls (call with consecutive, non-overlapping intervals); a sample less than half a period
     * after the last one already generated is skipped, so calls on [a, b], [b, c] do not repeat the sample at b. For
     * the most accurate IMU start t0 on the spline's knot grid (tStart() + i * knotSpacing()). */
    std::vector<dataset::ImuSample> generate(double t0, double t1, std::vector<ImuTruth>* truth = nullptr);

   private:
    TrajectorySpline spline_;  ///< a copy (shares the fitted spline): no dangling reference to a temporary
    ImuNoiseOptions options_;
    std::optional<ImuBiasTrajectory> bias_trajectory_;
    std::mt19937_64 rng_;
    Eigen::Vector3d gyro_bias_, acc_bias_;
    double last_t_ = -1e300;  ///< time of the last generated sample
};

}  // namespace quasiloc::sim
