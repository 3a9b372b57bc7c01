#include <quasiloc/core/error.h>
#include <quasiloc/dataset/calibration.h>
#include <quasiloc/sim/imu_synthesizer.h>

#include <cmath>
#include <mrpt/config/CConfigFileBase.h>
#include <cstdio>
#include <filesystem>

namespace quasiloc::sim
{
namespace
{
std::string fullPrecision(double v)
{
    char buf[40];
    std::snprintf(buf, sizeof(buf), "%.17g", v);
    return buf;
}

std::string vectorString(const Eigen::Vector3d& v)
{
    return "[" + fullPrecision(v.x()) + " " + fullPrecision(v.y()) + " " + fullPrecision(v.z()) + "]";
}

Eigen::Vector3d readVector3(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
                            const std::string& key, const Eigen::Vector3d& default_value)
{
    const std::string input = "INI [" + section + "] " + key;
    std::vector<double> dflt{default_value.x(), default_value.y(), default_value.z()}, values;
    try
    {
        cfg.read_vector(section, key, dflt, values);
    }
    catch (const std::exception& e)
    {
        throw core::InputError(input, std::string("expected 3 numbers like [0 0 0]: ") + e.what());
    }
    core::require(values.size() == 3, input, "expected 3 numbers like [0 0 0], got " + std::to_string(values.size()));
    return {values[0], values[1], values[2]};
}

/** A mode key: one of the enum's names exactly (no numbers, unlike CConfigFileBase::read_enum). */
template <typename Enum>
Enum readMode(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
              Enum default_value, const std::string& names)
{
    const std::string value = cfg.read_string_first_word(section, key, "", false);
    if (value.empty()) return default_value;
    try
    {
        return mrpt::typemeta::TEnumType<Enum>::name2value(value);
    }
    catch (const std::exception&)
    {
        throw core::InputError("INI [" + section + "] " + key, "'" + value + "' is not one of: " + names);
    }
}

template <typename Enum>
std::string modeName(Enum value)
{
    return mrpt::typemeta::TEnumType<Enum>::value2name(value);
}

Eigen::Vector3d gaussian3(std::mt19937_64& rng, double sigma)
{
    std::normal_distribution<double> normal(0.0, 1.0);
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i) v[i] = normal(rng);  // explicit order: deterministic across compilers' eval order
    return sigma * v;
}
}  // namespace

void ImuNoiseOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    source = readMode(cfg, section, "source", source, "synthetic, real");
    MRPT_LOAD_CONFIG_VAR(real_imu_csv, string, cfg, section);
    MRPT_LOAD_CONFIG_VAR(rate_hz, double, cfg, section);
    MRPT_LOAD_CONFIG_VAR(gyroscope_noise_density, double, cfg, section);
    MRPT_LOAD_CONFIG_VAR(gyroscope_random_walk, double, cfg, section);
    MRPT_LOAD_CONFIG_VAR(accelerometer_noise_density, double, cfg, section);
    MRPT_LOAD_CONFIG_VAR(accelerometer_random_walk, double, cfg, section);
    MRPT_LOAD_CONFIG_VAR(gravity_m_s2, double, cfg, section);
    MRPT_LOAD_CONFIG_VAR(noise_enabled, bool, cfg, section);
    seed = cfg.read_uint64_t(section, "seed", seed);
    bias = readMode(cfg, section, "bias", bias, "euroc_groundtruth, random_walk");
    MRPT_LOAD_CONFIG_VAR(bias_file, string, cfg, section);
    initial_gyro_bias = readVector3(cfg, section, "initial_gyro_bias", initial_gyro_bias);
    initial_acc_bias = readVector3(cfg, section, "initial_acc_bias", initial_acc_bias);
}

void ImuNoiseOptions::saveToConfigFile(mrpt::config::CConfigFileBase& cfg, const std::string& section) const
{
    cfg.write(section, "source", modeName(source));
    cfg.write(section, "real_imu_csv", real_imu_csv);
    cfg.write(section, "rate_hz", fullPrecision(rate_hz));
    cfg.write(section, "gyroscope_noise_density", fullPrecision(gyroscope_noise_density));
    cfg.write(section, "gyroscope_random_walk", fullPrecision(gyroscope_random_walk));
    cfg.write(section, "accelerometer_noise_density", fullPrecision(accelerometer_noise_density));
    cfg.write(section, "accelerometer_random_walk", fullPrecision(accelerometer_random_walk));
    cfg.write(section, "gravity_m_s2", fullPrecision(gravity_m_s2));
    cfg.write(section, "noise_enabled", std::string(noise_enabled ? "true" : "false"));
    cfg.write(section, "seed", std::to_string(seed));
    cfg.write(section, "bias", modeName(bias));
    cfg.write(section, "bias_file", bias_file);
    cfg.write(section, "initial_gyro_bias", vectorString(initial_gyro_bias));
    cfg.write(section, "initial_acc_bias", vectorString(initial_acc_bias));
}

void ImuNoiseOptions::check(const std::string& input) const
{
    using core::require;
    require(std::isfinite(rate_hz) && rate_hz > 0, input, "rate_hz must be > 0 (got " + fullPrecision(rate_hz) + ")");
    const std::pair<const char*, double> densities[] = {
        {"gyroscope_noise_density", gyroscope_noise_density},
        {"gyroscope_random_walk", gyroscope_random_walk},
        {"accelerometer_noise_density", accelerometer_noise_density},
        {"accelerometer_random_walk", accelerometer_random_walk},
        {"gravity_m_s2", gravity_m_s2}};
    for (const auto& [key, value] : densities)
        require(std::isfinite(value) && value >= 0, input,
                std::string(key) + " must be finite and >= 0 (got " + fullPrecision(value) + ")");
    require(initial_gyro_bias.allFinite(), input, "initial_gyro_bias must be finite");
    require(initial_acc_bias.allFinite(), input, "initial_acc_bias must be finite");
    require(real_imu_csv.empty() || source == ImuSource::real, input,
            "real_imu_csv is read only with source = real (got source = " + modeName(source) + ")");
    require(bias_file.empty() || bias == ImuBiasModel::euroc_groundtruth, input,
            "bias_file is read only with bias = euroc_groundtruth (got bias = " + modeName(bias) + ")");
}

void ImuNoiseOptions::loadFromEurocYaml(const std::string& path)
{
    const dataset::ImuCalibration c = dataset::imuCalibrationFromYaml(path);
    rate_hz = c.rate_hz;
    gyroscope_noise_density = c.gyroscope_noise_density;
    gyroscope_random_walk = c.gyroscope_random_walk;
    accelerometer_noise_density = c.accelerometer_noise_density;
    accelerometer_random_walk = c.accelerometer_random_walk;
    check(path);
}

ImuSynthesizer::ImuSynthesizer(const TrajectorySpline& spline, const ImuNoiseOptions& options,
                               std::optional<ImuBiasTrajectory> biases)
    : spline_(spline),
      options_(options),
      bias_trajectory_(std::move(biases)),
      rng_(options.seed),
      gyro_bias_(options.initial_gyro_bias),
      acc_bias_(options.initial_acc_bias)
{
    options_.check("ImuNoiseOptions");
}

std::vector<dataset::ImuSample> ImuSynthesizer::generate(double t0, double t1, std::vector<ImuTruth>* truth)
{
    std::vector<dataset::ImuSample> out;
    if (!(t1 >= t0)) return out;
    const double dt = 1.0 / options_.rate_hz;
    const auto n = static_cast<long long>(std::floor((t1 - t0) * options_.rate_hz + 1e-6));
    const Eigen::Vector3d g_world(0, 0, -options_.gravity_m_s2);
    const double sigma_gyro = options_.gyroscope_noise_density / std::sqrt(dt);
    const double sigma_acc = options_.accelerometer_noise_density / std::sqrt(dt);
    const double step_gyro = options_.gyroscope_random_walk * std::sqrt(dt);
    const double step_acc = options_.accelerometer_random_walk * std::sqrt(dt);
    out.reserve(static_cast<size_t>(n + 1));
    for (long long k = 0; k <= n; ++k)
    {
        const double t = t0 + static_cast<double>(k) * dt;  // no accumulated rounding
        if (t < last_t_ + 0.5 * dt) continue;               // already generated by the previous call
        const BodyState st = spline_.evaluate(t);
        if (bias_trajectory_) bias_trajectory_->at(t, gyro_bias_, acc_bias_);
        dataset::ImuSample s;
        s.t = t;
        s.gyro = st.omega_body + gyro_bias_;
        s.acc = st.R_world_body.transpose() * (st.a_world - g_world) + acc_bias_;
        if (truth) truth->push_back({t, gyro_bias_, acc_bias_});
        if (options_.noise_enabled)
        {
            s.gyro += gaussian3(rng_, sigma_gyro);
            s.acc += gaussian3(rng_, sigma_acc);
            if (!bias_trajectory_)
            {
                gyro_bias_ += gaussian3(rng_, step_gyro);
                acc_bias_ += gaussian3(rng_, step_acc);
            }
        }
        out.push_back(s);
        last_t_ = t;
    }
    return out;
}

}  // namespace quasiloc::sim
