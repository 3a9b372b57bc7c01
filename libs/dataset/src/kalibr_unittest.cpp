// Kalibr camchain and IMU YAML files: read against EuRoC's own calibration, written and read back, bad files named.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <quasiloc/core/error.h>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/dataset/kalibr.h>

#include "test_helpers.h"

using namespace quasiloc::dataset;
using quasiloc::dataset::test::TempDir;

namespace
{
const std::string kCalib = std::string(QUASILOC_SHARED_DIR) + "/data/euroc/calib/";

// EuRoC's camchain as Kalibr writes it (T_cam_imu is the inverse of sensor.yaml's T_BS; no T_cn_cnm1, so the
// stereo extrinsics follow from both T_cam_imu), with Kalibr's compact block sequences.
const char* kEurocCamchain = R"(cam0:
  T_cam_imu:
  - [0.0148655429817943, 0.999557249008346, -0.0257744366974403, 0.0652229095355311]
  - [-0.999880929698575, 0.0149672133247192, 0.00375618835796697, -0.0207063854927194]
  - [0.00414029679422404, 0.025715529947966, 0.999660727177902, -0.00805460246002952]
  - [0.0, 0.0, 0.0, 1.0]
  cam_overlaps: [1]
  camera_model: pinhole
  distortion_coeffs: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]
  distortion_model: radtan
  intrinsics: [458.654, 457.296, 367.215, 248.375]
  resolution: [752, 480]
  rostopic: /cam0/image_raw
cam1:
  T_cam_imu:
  - [0.012555267089103, 0.999598781151433, -0.0253898008917465, -0.0449019806825087]
  - [-0.999755099723116, 0.0130119051815039, 0.0179005838252513, -0.0205697712589152]
  - [0.0182237714554433, 0.0251588363115524, 0.999517347077547, -0.0086381351260281]
  - [0.0, 0.0, 0.0, 1.0]
  cam_overlaps: [0]
  camera_model: pinhole
  distortion_coeffs: [-0.28368365, 0.07451284, -0.00010473, -3.55590700e-05]
  distortion_model: radtan
  intrinsics: [457.587, 456.134, 379.999, 255.238]
  resolution: [752, 480]
  rostopic: /cam1/image_raw
)";

std::string write(const TempDir& dir, const std::string& name, const std::string& text)
{
    const std::string path = dir.path() + "/" + name;
    std::ofstream(path) << text;
    return path;
}

std::string errorOf(const std::function<void()>& f)
{
    try
    {
        f();
    }
    catch (const quasiloc::core::InputError& e)
    {
        return e.what();
    }
    return "";
}
}  // namespace

TEST(Kalibr, EurocCamchainGivesTheRigOfEurocSensorYaml)
{
    TempDir dir;
    const auto rig = stereoRigFromKalibr(write(dir, "camchain.yaml", kEurocCamchain));
    const auto euroc = quasiloc::core::StereoRig::fromEuroc(kCalib + "cam0_sensor.yaml", kCalib + "cam1_sensor.yaml");
    EXPECT_EQ(rig.left.width, 752);
    EXPECT_DOUBLE_EQ(rig.left.fx, euroc.left.fx);
    EXPECT_DOUBLE_EQ(rig.right.cy, euroc.right.cy);
    EXPECT_EQ(rig.left.model, quasiloc::core::DistortionModel::RadTan);
    EXPECT_DOUBLE_EQ(rig.right.dist[3], euroc.right.dist[3]);
    EXPECT_NEAR((rig.T_body_left.translation() - euroc.T_body_left.translation()).norm(), 0, 1e-9);
    EXPECT_NEAR((rig.T_left_right.translation() - euroc.T_left_right.translation()).norm(), 0, 1e-6);
    EXPECT_NEAR(rig.baseline(), 0.110078, 1e-5);
}

TEST(Kalibr, ACamchainWrittenAndReadBackIsTheSameRig)
{
    TempDir dir;
    auto rig = stereoRigFromKalibr(write(dir, "a.yaml", kEurocCamchain));
    rig.right.model = quasiloc::core::DistortionModel::Equidistant;  // pinhole-equidistant too
    const std::string text = kalibrCamchainText(rig, "/l", "/r", "test rig");
    EXPECT_NE(text.find("T_cn_cnm1"), std::string::npos);
    EXPECT_NE(text.find("equidistant"), std::string::npos);
    const auto back = stereoRigFromKalibr(write(dir, "b.yaml", text));
    EXPECT_EQ(back.right.model, quasiloc::core::DistortionModel::Equidistant);
    EXPECT_DOUBLE_EQ(back.left.cx, rig.left.cx);
    EXPECT_DOUBLE_EQ(back.right.dist[1], rig.right.dist[1]);
    EXPECT_NEAR((back.T_left_right.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>() -
                 rig.T_left_right.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>())
                    .norm(),
                0, 1e-14);
    EXPECT_NEAR((back.T_body_left.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>() -
                 rig.T_body_left.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>())
                    .norm(),
                0, 1e-14);
}

TEST(Kalibr, ImuYamlFlatNestedAndEurocAllRead)
{
    TempDir dir;
    const auto flat = imuCalibrationFromKalibr(write(dir, "imu.yaml",
                                                     "accelerometer_noise_density: 0.002\n"
                                                     "accelerometer_random_walk: 0.003\n"
                                                     "gyroscope_noise_density: 1.6968e-04\n"
                                                     "gyroscope_random_walk: 1.9393e-05\n"
                                                     "rostopic: /imu0\nupdate_rate: 200.0\n"));
    EXPECT_DOUBLE_EQ(flat.rate_hz, 200);
    EXPECT_DOUBLE_EQ(flat.gyroscope_noise_density, 1.6968e-04);
    const auto nested = imuCalibrationFromKalibr(write(dir, "imu-result.yaml",
                                                       "imu0:\n  accelerometer_noise_density: 0.01\n"
                                                       "  accelerometer_random_walk: 0.0002\n"
                                                       "  gyroscope_noise_density: 0.005\n"
                                                       "  gyroscope_random_walk: 4.0e-06\n"
                                                       "  model: calibrated\n  update_rate: 100.0\n"));
    EXPECT_DOUBLE_EQ(nested.rate_hz, 100);
    EXPECT_DOUBLE_EQ(nested.gyroscope_random_walk, 4e-6);
    const auto euroc = imuCalibrationFromKalibr(kCalib + "imu0_sensor.yaml");  // %YAML:1.0, rate_hz
    EXPECT_DOUBLE_EQ(euroc.rate_hz, 200);
    const auto back = imuCalibrationFromKalibr(write(dir, "back.yaml", kalibrImuText(euroc, "/imu0")));
    EXPECT_DOUBLE_EQ(back.accelerometer_random_walk, euroc.accelerometer_random_walk);
}

TEST(Kalibr, BadFilesAreErrorsNamingTheFileAndTheKey)
{
    TempDir dir;
    std::string text = kEurocCamchain;
    text.replace(text.find("radtan"), 6, "fov");
    const std::string fov = write(dir, "fov.yaml", text);
    EXPECT_NE(errorOf([&] { stereoRigFromKalibr(fov); }).find("fov.yaml: cam0.distortion_model"), std::string::npos);
    const std::string mono =
        write(dir, "mono.yaml", std::string(kEurocCamchain).substr(0, std::string(kEurocCamchain).find("cam1:")));
    EXPECT_NE(errorOf([&] { stereoRigFromKalibr(mono); }).find("mono.yaml: cam1"), std::string::npos);
    EXPECT_NE(errorOf([&] { stereoRigFromKalibr(dir.path() + "/none.yaml"); }).find("none.yaml"), std::string::npos);
    const std::string imu = write(dir, "imu.yaml", "update_rate: 200\ngyroscope_noise_density: 0.1\n");
    EXPECT_NE(errorOf([&] { imuCalibrationFromKalibr(imu); }).find("imu.yaml: gyroscope_random_walk"),
              std::string::npos);
    // A camera or imu0 that is a single value: yaml-cpp throws an unnamed BadSubscript on a key lookup in it.
    const std::string scalar_cam = write(dir, "scalar_cam.yaml", "cam0: 5\ncam1: {}\n");
    EXPECT_NE(errorOf([&] { stereoRigFromKalibr(scalar_cam); }).find("scalar_cam.yaml: cam0"), std::string::npos);
    const std::string scalar_imu = write(dir, "scalar_imu.yaml", "imu0: 200\n");
    EXPECT_NE(errorOf([&] { imuCalibrationFromKalibr(scalar_imu); }).find("scalar_imu.yaml: imu0"), std::string::npos);
}
