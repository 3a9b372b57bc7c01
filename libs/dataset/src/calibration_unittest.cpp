// The calibration INI: written and read back whole; every bad [imu] value is an error naming the file and the key.
#include <gtest/gtest.h>

#include <fstream>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/dataset/calibration.h>

#include "test_helpers.h"

using namespace quasiloc::dataset;
using quasiloc::dataset::test::TempDir;

namespace
{
const std::string kCalib = std::string(QUASILOC_SHARED_DIR) + "/data/euroc/calib/";

SensorCalibration eurocCalibration()
{
    SensorCalibration c;
    c.rig = quasiloc::core::StereoRig::fromEuroc(kCalib + "cam0_sensor.yaml", kCalib + "cam1_sensor.yaml");
    c.imu = imuCalibrationFromYaml(kCalib + "imu0_sensor.yaml");
    return c;
}

/** The error loadCalibration gives for a file whose [imu] line `from` is replaced by `to` ("" if none). */
std::string errorWith(const TempDir& dir, const std::string& from, const std::string& to)
{
    std::string text = calibrationText(eurocCalibration());
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    const std::string path = dir / "calib.ini";
    std::ofstream(path) << text;
    try
    {
        loadCalibration(path);
    }
    catch (const quasiloc::core::InputError& e)
    {
        return e.what();
    }
    return "";
}
}  // namespace

TEST(Calibration, ReadsBackWhatItWrote)
{
    TempDir dir;
    SensorCalibration c = eurocCalibration();
    c.imu->gyroscope_bias = Eigen::Vector3d(-0.0023, 0.0249, 0.0817);
    c.imu->gyroscope_bias_sigma = 0.001;
    saveCalibration(c, dir / "calib.ini", "a test\ntwo lines");
    const SensorCalibration r = loadCalibration(dir / "calib.ini");
    ASSERT_TRUE(r.imu);
    EXPECT_EQ(r.imu->rate_hz, 200);
    EXPECT_DOUBLE_EQ(r.imu->gyroscope_noise_density, 1.6968e-04);
    EXPECT_DOUBLE_EQ(r.imu->accelerometer_random_walk, 3.0e-3);
    EXPECT_LT((r.imu->gyroscope_bias - c.imu->gyroscope_bias).norm(), 1e-9);
    EXPECT_DOUBLE_EQ(r.imu->gyroscope_bias_sigma, 0.001);
    EXPECT_EQ(r.imu->accelerometer_bias_sigma, kUnknownAccBiasSigma);
    EXPECT_DOUBLE_EQ(r.rig.left.fx, c.rig.left.fx);
}

TEST(Calibration, ANoiseModelFromTheYamlLeavesTheBiasUnknown)
{
    const ImuCalibration imu = imuCalibrationFromYaml(kCalib + "imu0_sensor.yaml");
    EXPECT_EQ(imu.gyroscope_bias, Eigen::Vector3d::Zero());
    EXPECT_EQ(imu.gyroscope_bias_sigma, kUnknownGyroBiasSigma);
    EXPECT_THROW(imuCalibrationFromYaml(kCalib + "cam0_sensor.yaml"), quasiloc::core::InputError);
}

TEST(Calibration, AMissingBadOrUnknownImuKeyNamesTheFileAndTheKey)
{
    TempDir dir;
    const std::string file = dir / "calib.ini";
    for (const auto& [from, to, key] : std::vector<std::tuple<std::string, std::string, std::string>>{
             {"gyroscope_noise_density = 0.00016968", "", "gyroscope_noise_density"},
             {"rate_hz = 200", "rate_hz = fast", "rate_hz"},
             {"accelerometer_random_walk = 0.003", "accelerometer_random_walk = -1", "accelerometer_random_walk"},
             {"gravity_m_s2 = 9.81", "gravity_m_s2 = 9.81\ngyro_noise = 1", "gyro_noise"},
             {"gyroscope_bias = [0 0 0]", "gyroscope_bias = [0 0]", "gyroscope_bias"}})
    {
        const std::string error = errorWith(dir, from, to);
        EXPECT_NE(error.find(file), std::string::npos) << error;
        EXPECT_NE(error.find(key), std::string::npos) << error;
    }
}

TEST(Calibration, AFileWithoutImuHasTheRigOnlyAndTheTrackerAsksForIt)
{
    TempDir dir;
    SensorCalibration c = eurocCalibration();
    c.imu.reset();
    saveCalibration(c, dir / "calib.ini", "rig only");
    const SensorCalibration r = loadCalibration(dir / "calib.ini");
    EXPECT_FALSE(r.imu);
    EXPECT_THROW(r.requireImu(dir / "calib.ini"), quasiloc::core::InputError);
    EXPECT_THROW(loadCalibration(dir / "none.ini"), quasiloc::core::InputError);
}
