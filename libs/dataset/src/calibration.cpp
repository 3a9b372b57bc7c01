// The sensor calibration INI: stereo rig + IMU noise model (calibration.h).
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>
#include <filesystem>
#include <opencv2/core/persistence.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/core/ini_read.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/dataset/calibration.h>
#include <quasiloc/dataset/kalibr.h>
#include <set>
#include <sstream>

namespace quasiloc::dataset
{
namespace
{
const char* kImu = "imu";

std::string keyName(const std::string& key) { return core::iniKeyName(kImu, key); }

std::string fullPrecision(double v)
{
    std::ostringstream s;
    s.precision(10);
    s << v;
    return s.str();
}

std::string vectorText(const Eigen::Vector3d& v)
{
    return "[" + fullPrecision(v.x()) + " " + fullPrecision(v.y()) + " " + fullPrecision(v.z()) + "]";
}

double requiredDouble(const mrpt::config::CConfigFileBase& cfg, const std::string& key)
{
    core::require(!cfg.read_string(kImu, key, "", false).empty(), keyName(key), "missing (required)");
    return core::readIniDouble(cfg, kImu, key, 0.0);
}

std::optional<Eigen::Vector3d> optionalVector3(const mrpt::config::CConfigFileBase& cfg, const std::string& key)
{
    const std::vector<double> v = core::readIniVector(cfg, kImu, key, {});
    if (v.empty()) return std::nullopt;
    core::require(v.size() == 3, keyName(key), "must hold 3 values [x y z] (got " + std::to_string(v.size()) + ")");
    return Eigen::Vector3d(v[0], v[1], v[2]);
}

ImuCalibration readImu(const mrpt::config::CConfigFileBase& cfg)
{
    static const std::set<std::string> known = {"rate_hz",
                                                "gyroscope_noise_density",
                                                "gyroscope_random_walk",
                                                "accelerometer_noise_density",
                                                "accelerometer_random_walk",
                                                "gravity_m_s2",
                                                "gyroscope_bias",
                                                "accelerometer_bias",
                                                "gyroscope_bias_sigma",
                                                "accelerometer_bias_sigma"};
    std::vector<std::string> keys;
    cfg.getAllKeys(kImu, keys);
    for (const std::string& k : keys) core::require(known.count(k) > 0, keyName(k), "unknown key (typo?)");
    ImuCalibration imu;
    imu.rate_hz = requiredDouble(cfg, "rate_hz");
    imu.gyroscope_noise_density = requiredDouble(cfg, "gyroscope_noise_density");
    imu.gyroscope_random_walk = requiredDouble(cfg, "gyroscope_random_walk");
    imu.accelerometer_noise_density = requiredDouble(cfg, "accelerometer_noise_density");
    imu.accelerometer_random_walk = requiredDouble(cfg, "accelerometer_random_walk");
    imu.gravity_m_s2 = core::readIniDouble(cfg, kImu, "gravity_m_s2", imu.gravity_m_s2);
    if (const auto b = optionalVector3(cfg, "gyroscope_bias")) imu.gyroscope_bias = *b;
    if (const auto b = optionalVector3(cfg, "accelerometer_bias")) imu.accelerometer_bias = *b;
    imu.gyroscope_bias_sigma = core::readIniDouble(cfg, kImu, "gyroscope_bias_sigma", imu.gyroscope_bias_sigma);
    imu.accelerometer_bias_sigma =
        core::readIniDouble(cfg, kImu, "accelerometer_bias_sigma", imu.accelerometer_bias_sigma);
    imu.check("[imu]");
    return imu;
}
}  // namespace

void ImuCalibration::check(const std::string& input) const
{
    const std::pair<const char*, double> positive[] = {{"rate_hz", rate_hz},
                                                       {"gyroscope_noise_density", gyroscope_noise_density},
                                                       {"gyroscope_random_walk", gyroscope_random_walk},
                                                       {"accelerometer_noise_density", accelerometer_noise_density},
                                                       {"accelerometer_random_walk", accelerometer_random_walk},
                                                       {"gravity_m_s2", gravity_m_s2},
                                                       {"gyroscope_bias_sigma", gyroscope_bias_sigma},
                                                       {"accelerometer_bias_sigma", accelerometer_bias_sigma}};
    for (const auto& [key, value] : positive)
        core::require(std::isfinite(value) && value > 0, input + " " + key,
                      "must be a finite number > 0 (got " + fullPrecision(value) + ")");
    core::require(gyroscope_bias.allFinite(), input + " gyroscope_bias", "must be finite");
    core::require(accelerometer_bias.allFinite(), input + " accelerometer_bias", "must be finite");
}

const ImuCalibration& SensorCalibration::requireImu(const std::string& input) const
{
    core::require(imu.has_value(), input,
                  "no [imu] section (the IMU noise model: rate_hz, noise densities, random walks)");
    return *imu;
}

SensorCalibration loadCalibration(const std::string& path)
{
    core::require(std::filesystem::is_regular_file(path), path, "calibration INI file not found");
    mrpt::config::CConfigFile cfg(path);
    SensorCalibration c;
    try
    {
        c.rig = core::StereoRig::loadFromIni(cfg, "camera_");
        if (cfg.sectionExists(kImu)) c.imu = readImu(cfg);
    }
    catch (const core::InputError& e)
    {
        throw core::InputError(path, e.what());
    }
    return c;
}

ImuCalibration imuCalibrationFromIni(const std::string& path)
{
    core::require(std::filesystem::is_regular_file(path), path, "INI file not found");
    mrpt::config::CConfigFile cfg(path);
    core::require(cfg.sectionExists(kImu), path, "no [imu] section (the IMU noise model)");
    try
    {
        return readImu(cfg);
    }
    catch (const core::InputError& e)
    {
        throw core::InputError(path, e.what());
    }
}

std::string calibrationText(const SensorCalibration& calibration)
{
    mrpt::config::CConfigFileMemory cfg;
    calibration.rig.saveToIni(cfg, "camera_");
    if (const auto& imu = calibration.imu)
    {
        cfg.write(kImu, "rate_hz", fullPrecision(imu->rate_hz));
        cfg.write(kImu, "gyroscope_noise_density", fullPrecision(imu->gyroscope_noise_density));
        cfg.write(kImu, "gyroscope_random_walk", fullPrecision(imu->gyroscope_random_walk));
        cfg.write(kImu, "accelerometer_noise_density", fullPrecision(imu->accelerometer_noise_density));
        cfg.write(kImu, "accelerometer_random_walk", fullPrecision(imu->accelerometer_random_walk));
        cfg.write(kImu, "gravity_m_s2", fullPrecision(imu->gravity_m_s2));
        cfg.write(kImu, "gyroscope_bias", vectorText(imu->gyroscope_bias));
        cfg.write(kImu, "gyroscope_bias_sigma", fullPrecision(imu->gyroscope_bias_sigma));
        cfg.write(kImu, "accelerometer_bias", vectorText(imu->accelerometer_bias));
        cfg.write(kImu, "accelerometer_bias_sigma", fullPrecision(imu->accelerometer_bias_sigma));
    }
    return cfg.getContent();
}

void saveCalibration(const SensorCalibration& calibration, const std::string& path, const std::string& header)
{
    std::string commented;
    std::istringstream lines(header);
    for (std::string line; std::getline(lines, line);) commented += "# " + line + "\n";
    core::writeTextFileAtomically(path, commented + calibrationText(calibration));
}

ImuCalibration imuCalibrationFromYaml(const std::string& yaml_path)
{
    // EuRoC's sensor.yaml and Kalibr's IMU files are read by the same reader (kalibr.h).
    return imuCalibrationFromKalibr(yaml_path);
}

}  // namespace quasiloc::dataset
