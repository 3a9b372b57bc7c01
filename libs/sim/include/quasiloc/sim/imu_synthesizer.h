#pragma once
// IMU synthesis from a TrajectorySpline: specific force f = R_world_body^T (a_world - g_world) and angular
// rate omega_body, plus discrete-time white noise and bias random walk with continuous-time densities
// (Kalibr/EuRoC convention: sigma_discrete = density / sqrt(dt) for white noise,
// bias step sigma = random_walk * sqrt(dt)). Deterministic for a seed.
// Sample k carries the bias b_k; b_{k+1} = b_k + N(0, (random_walk sqrt(dt))^2). With noise_enabled = false
// the samples are exact, plus the constant initial biases (zero by default).
#include <mrpt/config/CLoadableOptions.h>
#include <quasiloc/dataset/frame.h>
#include <quasiloc/sim/trajectory_spline.h>
#include <random>
#include <vector>

namespace quasiloc::sim
{
struct ImuNoiseOptions : public mrpt::config::CLoadableOptions
{
    double rate_hz = 200;
    double gyroscope_noise_density = 1.6968e-04;      ///< rad/s/sqrt(Hz)
    double gyroscope_random_walk = 1.9393e-05;        ///< rad/s^2/sqrt(Hz)
    double accelerometer_noise_density = 2.0000e-3;   ///< m/s^2/sqrt(Hz)
    double accelerometer_random_walk = 3.0000e-3;     ///< m/s^3/sqrt(Hz)
    double gravity_m_s2 = 9.81;
    bool noise_enabled = true;
    uint64_t seed = 1;
    Eigen::Vector3d initial_gyro_bias = Eigen::Vector3d::Zero();
    Eigen::Vector3d initial_acc_bias = Eigen::Vector3d::Zero();

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
    void check(const std::string& input) const;
    /** Densities from an EuRoC/Kalibr imu sensor.yaml (rate_hz too). */
    void loadFromEurocYaml(const std::string& path);
};

/** One synthesized sample with the true biases that were added (for tests and evaluation). */
struct ImuTruth
{
    double t = 0;
    Eigen::Vector3d gyro_bias, acc_bias;
};

class ImuSynthesizer
{
   public:
    /** The body frame of the spline is the IMU frame. InputError when options.check() fails. */
    ImuSynthesizer(const TrajectorySpline& spline, const ImuNoiseOptions& options);
    /** Samples at t0, t0 + 1/rate, ... <= t1 (t0, t1 within the spline, else std::out_of_range). Continues the bias random walk
     *  across calls (call with consecutive, non-overlapping intervals); a sample less than half a period after
     *  the last one already generated is skipped, so calls on [a, b], [b, c] do not repeat the sample at b.
     *  For the most accurate IMU start t0 on the spline's knot grid (tStart() + i * knotSpacing()). */
    std::vector<dataset::ImuSample> generate(double t0, double t1, std::vector<ImuTruth>* truth = nullptr);

   private:
    TrajectorySpline spline_;  ///< a copy (shares the fitted spline): no dangling reference to a temporary
    ImuNoiseOptions options_;
    std::mt19937_64 rng_;
    Eigen::Vector3d gyro_bias_, acc_bias_;
    double last_t_ = -1e300;  ///< time of the last generated sample
};

}  // namespace quasiloc::sim
