// The IMU's bias models and the real-IMU replay of the simulation (imu_synthesizer.h): the bias trajectory,
// which bias model a configuration resolves to, and the real samples in the span of the simulated frames.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <quasiloc/core/error.h>
#include <quasiloc/sim/imu_synthesizer.h>
#include <random>

namespace quasiloc::sim
{
namespace
{
std::string fixed(double v, int decimals)
{
    char buf[48];
    std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
    return buf;
}

std::string spanText(double t0, double t1) { return "[" + fixed(t0, 3) + ", " + fixed(t1, 3) + "] s"; }

std::string vectorText(const Eigen::Vector3d& v, int decimals)
{
    return "(" + fixed(v.x(), decimals) + " " + fixed(v.y(), decimals) + " " + fixed(v.z(), decimals) + ")";
}
}  // namespace

ImuBiasTrajectory::ImuBiasTrajectory(std::vector<double> t, std::vector<Eigen::Vector3d> gyro_bias,
                                     std::vector<Eigen::Vector3d> acc_bias, std::string source)
    : t_(std::move(t)), gyro_(std::move(gyro_bias)), acc_(std::move(acc_bias)), source_(std::move(source))
{
    core::require(!t_.empty(), source_, "bias trajectory holds no sample");
    core::require(gyro_.size() == t_.size() && acc_.size() == t_.size(), source_,
                  "bias trajectory: times, gyro and acc biases differ in length");
    for (size_t i = 0; i < t_.size(); ++i)
    {
        core::require(std::isfinite(t_[i]) && gyro_[i].allFinite() && acc_[i].allFinite(), source_,
                      "bias trajectory sample " + std::to_string(i) + " is not finite");
        core::require(i == 0 || t_[i] > t_[i - 1], source_,
                      "bias trajectory times must increase (sample " + std::to_string(i) + ")");
    }
}

ImuBiasTrajectory ImuBiasTrajectory::fromEuroc(const dataset::EurocBiasCsv& csv)
{
    std::vector<double> t;
    t.reserve(csv.t_ns.size());
    for (const std::int64_t ns : csv.t_ns) t.push_back(static_cast<double>(ns) * 1e-9);
    return ImuBiasTrajectory(std::move(t), csv.gyro_bias, csv.acc_bias, csv.path);
}

void ImuBiasTrajectory::at(double t, Eigen::Vector3d& gyro_bias, Eigen::Vector3d& acc_bias) const
{
    const auto hi = std::upper_bound(t_.begin(), t_.end(), t);
    if (hi == t_.begin() || hi == t_.end())  // outside the span: hold the first / last value
    {
        const size_t i = hi == t_.begin() ? 0 : t_.size() - 1;
        gyro_bias = gyro_[i];
        acc_bias = acc_[i];
        return;
    }
    const auto i1 = static_cast<size_t>(hi - t_.begin()), i0 = i1 - 1;
    const double w = (t - t_[i0]) / (t_[i1] - t_[i0]);
    gyro_bias = (1 - w) * gyro_[i0] + w * gyro_[i1];
    acc_bias = (1 - w) * acc_[i0] + w * acc_[i1];
}

void drawInitialBiases(ImuNoiseOptions& o)
{
    std::mt19937_64 rng(o.seed ^ 0xB1A5B1A5B1A5ull);
    std::uniform_real_distribution<double> magnitude(0.3, 1.0);
    std::bernoulli_distribution positive(0.5);
    for (int i = 0; i < 3; ++i)
    {
        o.initial_gyro_bias[i] = (positive(rng) ? 1 : -1) * magnitude(rng) * o.gyro_bias_max_rad_s;
        o.initial_acc_bias[i] = (positive(rng) ? 1 : -1) * magnitude(rng) * o.acc_bias_max_m_s2;
    }
}

ResolvedImuBias resolveImuBias(const ImuNoiseOptions& o, const std::string& shared_dir, const std::string& sequence,
                               double t0_s, double t1_s, const std::string& input)
{
    ResolvedImuBias r;
    const std::string walk = "random walk from gyro " + vectorText(o.initial_gyro_bias, 4) + " rad/s, acc " +
                             vectorText(o.initial_acc_bias, 3) + " m/s^2" +
                             (o.noise_enabled ? "" : " (held constant: noise_enabled = false)");
    if (o.bias == ImuBiasModel::random_walk || o.bias == ImuBiasModel::random_draw)
    {
        r.description = walk + (o.bias == ImuBiasModel::random_walk ? " (bias = random_walk)"
                                                                    : " (bias = random_draw: initial biases drawn)");
        return r;
    }
    std::string path = o.bias_file;
    if (path.empty())
    {
        path = shared_dir + "/data/euroc/groundtruth/body/" + sequence + ".csv";
        if (!std::filesystem::exists(path))
        {
            r.description =
                walk + " (bias = euroc_groundtruth, but " + sequence + " has no ground-truth bias file " + path + ")";
            return r;
        }
    }
    else
    {
        core::require(std::filesystem::is_regular_file(path), input + " [IMU] bias_file",
                      "'" + path + "' does not exist");
    }
    r.trajectory = ImuBiasTrajectory::fromEuroc(dataset::readEurocBiasCsv(path, o.rate_hz));
    const ImuBiasTrajectory& b = *r.trajectory;
    core::require(b.tStart() <= t1_s && b.tEnd() >= t0_s, path,
                  "covers " + spanText(b.tStart(), b.tEnd()) + ", the simulated IMU " + spanText(t0_s, t1_s) +
                      ": no overlap (a trajectory on another clock? use bias = random_walk)");
    Eigen::Vector3d g0, a0;
    b.at(t0_s, g0, a0);
    r.description = "EuRoC ground-truth biases of " + path + " interpolated at each sample (held outside " +
                    spanText(b.tStart(), b.tEnd()) + "); at the first sample gyro " + vectorText(g0, 4) +
                    " rad/s, acc " + vectorText(a0, 3) + " m/s^2";
    return r;
}

dataset::EurocImuCsv selectRealImu(const dataset::EurocImuCsv& real, std::int64_t t0_ns, std::int64_t t1_ns,
                                   double rate_hz)
{
    core::require(!real.t_ns.empty(), real.path, "holds no IMU sample");
    const auto period_ns = static_cast<std::int64_t>(1e9 / rate_hz);
    core::require(real.t_ns.front() <= t0_ns + period_ns && real.t_ns.back() >= t1_ns - period_ns, real.path,
                  "real IMU covers " + spanText(real.t_ns.front() * 1e-9, real.t_ns.back() * 1e-9) +
                      ", not the simulated frames " + spanText(t0_ns * 1e-9, t1_ns * 1e-9) +
                      " (source = real replays the file on the ground-truth clock: only its own sequence fits)");
    const auto b = std::lower_bound(real.t_ns.begin(), real.t_ns.end(), t0_ns) - real.t_ns.begin();
    const auto e = std::upper_bound(real.t_ns.begin(), real.t_ns.end(), t1_ns) - real.t_ns.begin();
    dataset::EurocImuCsv out;
    out.path = real.path;
    out.t_ns.assign(real.t_ns.begin() + b, real.t_ns.begin() + e);
    out.samples.assign(real.samples.begin() + b, real.samples.begin() + e);
    return out;
}

size_t snapToImuTicks(std::vector<std::int64_t>& t_ns, const std::vector<std::int64_t>& imu_t_ns,
                      std::int64_t tolerance_ns)
{
    size_t moved = 0;
    for (std::int64_t& t : t_ns)
    {
        const auto hi = std::lower_bound(imu_t_ns.begin(), imu_t_ns.end(), t);
        std::int64_t nearest = t, best = tolerance_ns + 1;
        if (hi != imu_t_ns.end() && *hi - t < best) best = *hi - t, nearest = *hi;
        if (hi != imu_t_ns.begin() && t - *(hi - 1) < best) best = t - *(hi - 1), nearest = *(hi - 1);
        if (best <= tolerance_ns && nearest != t)
        {
            t = nearest;
            ++moved;
        }
    }
    return moved;
}

}  // namespace quasiloc::sim
