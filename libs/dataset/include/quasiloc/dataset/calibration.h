#pragma once
// The sensor calibration every program reads: the stereo rig (core::StereoRig keys, sections camera_left,
// camera_right, camera_rig) and the IMU noise model (section [imu]), in one INI file. euroc2rawlog and sim-rawlog
// write it (saveCalibration), every program reads it through loadCalibration.
//
// [imu] keys (Kalibr / EuRoC sensor.yaml names and units):
//   rate_hz                      required, > 0
//   gyroscope_noise_density      required, rad/s/sqrt(Hz)
//   gyroscope_random_walk        required, rad/s^2/sqrt(Hz)
//   accelerometer_noise_density  required, m/s^2/sqrt(Hz)
//   accelerometer_random_walk    required, m/s^3/sqrt(Hz)
//   gravity_m_s2                 optional, 9.81
//   gyroscope_bias, accelerometer_bias             optional "[x y z]": a measured bias at the start (body frame)
//   gyroscope_bias_sigma, accelerometer_bias_sigma optional: its uncertainty. Without a measured bias the prior is
//                                zero with the sigmas of real MEMS biases (kUnknownGyroBiasSigma, ...), not a
//                                simulator's zero: EuRoC's ADIS16448 starts every sequence near (-0.002, 0.021,
//                                0.077) rad/s and (-0.02, 0.12, 0.08) m/s^2.
// Any other key in [imu] is an error (a typo must not pass silently).
#include <Eigen/Core>
#include <optional>
#include <quasiloc/core/stereo_rig.h>
#include <string>

namespace quasiloc::dataset
{
constexpr double kUnknownGyroBiasSigma = 0.1;  ///< rad/s: the scale of an uncalibrated MEMS gyroscope's bias
constexpr double kUnknownAccBiasSigma = 0.2;   ///< m/s^2

struct ImuCalibration
{
    double rate_hz = 200;
    double gyroscope_noise_density = 0, gyroscope_random_walk = 0;
    double accelerometer_noise_density = 0, accelerometer_random_walk = 0;
    double gravity_m_s2 = 9.81;
    Eigen::Vector3d gyroscope_bias = Eigen::Vector3d::Zero();
    Eigen::Vector3d accelerometer_bias = Eigen::Vector3d::Zero();
    double gyroscope_bias_sigma = kUnknownGyroBiasSigma;
    double accelerometer_bias_sigma = kUnknownAccBiasSigma;

    /** InputError naming `input` and the key for a value out of range. */
    void check(const std::string& input) const;
};

struct SensorCalibration
{
    core::StereoRig rig;
    std::optional<ImuCalibration> imu;  ///< absent when the file has no [imu] section

    /** The IMU calibration, or an InputError naming `input` when the file had none. */
    const ImuCalibration& requireImu(const std::string& input) const;
};

/** Reads a calibration INI. InputError naming the file and the key for a missing file, a missing or malformed
 *  value, an unknown [imu] key. */
SensorCalibration loadCalibration(const std::string& path);
/** The [imu] section of any INI file (the same keys and checks as loadCalibration's), for programs that take
 *  the cameras from elsewhere. InputError naming the file and the key. */
ImuCalibration imuCalibrationFromIni(const std::string& path);
/** Writes it atomically (the header comment first, '#' added to each line). */
void saveCalibration(const SensorCalibration& calibration, const std::string& path, const std::string& header);
/** The INI text saveCalibration writes (without the header). */
std::string calibrationText(const SensorCalibration& calibration);

/** The noise model of a Kalibr / EuRoC IMU sensor.yaml (rate_hz and the four densities; the bias stays unknown).
 *  InputError naming the file and the key for a missing or non-positive value. */
ImuCalibration imuCalibrationFromYaml(const std::string& yaml_path);

}  // namespace quasiloc::dataset
