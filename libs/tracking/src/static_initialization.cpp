// Static IMU initialization and the standstill detector (static_initialization.h).
#include <quasiloc/tracking/static_initialization.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace quasiloc::tracking
{
namespace
{
struct BlockMeans
{
    std::vector<Eigen::Vector3d> gyro, acc;
};

BlockMeans blockMeans(const std::vector<dataset::ImuSample>& samples, double block_s)
{
    BlockMeans m;
    if (samples.empty()) return m;
    const double t0 = samples.front().t;
    Eigen::Vector3d g = Eigen::Vector3d::Zero(), a = Eigen::Vector3d::Zero();
    size_t n = 0, block = 0;
    const auto flush = [&] {
        if (n == 0) return;
        m.gyro.push_back(g / double(n));
        m.acc.push_back(a / double(n));
        g.setZero();
        a.setZero();
        n = 0;
    };
    for (const dataset::ImuSample& s : samples)
    {
        const size_t b = size_t(std::floor((s.t - t0) / block_s));
        if (b != block) flush();
        block = b;
        g += s.gyro;
        a += s.acc;
        ++n;
    }
    // A last block shorter than half a block says little and would let a few samples decide: dropped.
    if (double(n) >= 0.5 * block_s / std::max(1e-9, (samples.back().t - t0) / double(samples.size())) || m.gyro.empty())
        flush();
    return m;
}

Eigen::Vector3d mean(const std::vector<Eigen::Vector3d>& v)
{
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (const auto& x : v) s += x;
    return v.empty() ? s : Eigen::Vector3d(s / double(v.size()));
}

double maxDeviation(const std::vector<Eigen::Vector3d>& v, const Eigen::Vector3d& m)
{
    double d = 0;
    for (const auto& x : v) d = std::max(d, (x - m).cwiseAbs().maxCoeff());
    return d;
}
}  // namespace

std::optional<StaticImuEstimate> staticImuEstimate(const std::vector<dataset::ImuSample>& samples,
                                                   double gyro_noise_density, const StandstillOptions& o,
                                                   std::string* why)
{
    std::ostringstream s;
    s.precision(3);
    const double span = samples.size() < 2 ? 0.0 : samples.back().t - samples.front().t;
    const BlockMeans m = blockMeans(samples, o.block_s);
    const Eigen::Vector3d gyro_mean = mean(m.gyro);
    const double gyro_dev = maxDeviation(m.gyro, gyro_mean), acc_dev = maxDeviation(m.acc, mean(m.acc));
    if (span < std::max(o.min_still_s, 2 * o.block_s))
        s << "standing span " << span << " s < " << o.min_still_s << " s";
    else if (gyro_dev > o.max_gyro_block_dev_rad_s)
        s << "moving: gyroscope block means deviate by " << gyro_dev << " rad/s (> " << o.max_gyro_block_dev_rad_s
          << ")";
    else if (acc_dev > o.max_acc_block_dev_m_s2)
        s << "moving: accelerometer block means deviate by " << acc_dev << " m/s^2 (> " << o.max_acc_block_dev_m_s2
          << ")";
    if (why) *why = s.str();
    if (!s.str().empty()) return std::nullopt;

    StaticImuEstimate e;
    e.span_s = span;
    // The last block is left out of the means: a motion that starts there may not show in the detector yet.
    const double t_guard = samples.back().t - o.block_s;
    Eigen::Vector3d g = Eigen::Vector3d::Zero(), a = Eigen::Vector3d::Zero();
    size_t n = 0;
    for (const dataset::ImuSample& x : samples)
        if (x.t <= t_guard)
        {
            g += x.gyro;
            a += x.acc;
            ++n;
        }
    e.gyro_bias = g / double(n);
    e.mean_specific_force = a / double(n);
    double var = 0;  // per axis, of the block means
    for (const auto& b : m.gyro) var += (b - gyro_mean).squaredNorm() / 3.0;
    const double blocks = double(m.gyro.size());
    const double spread_sigma = blocks > 1 ? std::sqrt(var / (blocks - 1)) / std::sqrt(blocks) : 0.0;
    e.gyro_bias_sigma =
        std::max({spread_sigma, gyro_noise_density / std::sqrt(std::max(span, 1e-6)), o.min_gyro_bias_sigma});
    return e;
}

ImuBiasPrior withStaticEstimate(const ImuBiasPrior& calibration, const std::optional<StaticImuEstimate>& estimate)
{
    if (!estimate) return calibration;
    ImuBiasPrior p = calibration;
    p.gyro_bias = estimate->gyro_bias;
    p.gyro_sigma = estimate->gyro_bias_sigma;
    std::ostringstream s;
    s.precision(3);
    s << "static initialization over " << estimate->span_s << " s";
    p.source = s.str();
    return p;
}

void StaticInitializer::add(const std::vector<dataset::ImuSample>& samples)
{
    if (moved_ || samples.empty()) return;
    samples_.insert(samples_.end(), samples.begin(), samples.end());
    const double t_oldest = samples_.back().t - options_.max_span_s;
    samples_.erase(samples_.begin(), std::find_if(samples_.begin(), samples_.end(),
                                                  [t_oldest](const dataset::ImuSample& x) { return x.t >= t_oldest; }));
    auto e = staticImuEstimate(samples_, gyro_noise_density_, options_);
    if (!e && samples_.back().t - samples_.front().t >= options_.min_still_s)
    {
        // Moving: the estimate of the standing span before (if any) stays; no later span is a start.
        moved_ = true;
        samples_.clear();
        return;
    }
    if (e) estimate_ = e;
}

std::optional<StaticImuEstimate> StaticInitializer::estimate() const { return estimate_; }

StandstillWatch::StandstillWatch(double gyro_noise_density, double span_s, const StandstillOptions& options)
    : gyro_noise_density_(gyro_noise_density), span_s_(span_s), options_(options)
{
    // The samples kept begin within one sample period after the span's start: most of the span counts.
    options_.min_still_s = 0.9 * span_s;
}

bool StandstillWatch::add(const std::vector<dataset::ImuSample>& samples)
{
    samples_.insert(samples_.end(), samples.begin(), samples.end());
    if (samples_.empty()) return false;
    const double t_oldest = samples_.back().t - span_s_;
    samples_.erase(samples_.begin(), std::find_if(samples_.begin(), samples_.end(),
                                                  [t_oldest](const dataset::ImuSample& x) { return x.t >= t_oldest; }));
    return bool(staticImuEstimate(samples_, gyro_noise_density_, options_));
}

}  // namespace quasiloc::tracking
