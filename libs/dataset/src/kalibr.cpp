// Kalibr camchain and IMU YAML files <-> the calibration INI's types (kalibr.h).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/yaml_read.h>
#include <quasiloc/dataset/kalibr.h>
#include <sstream>

using quasiloc::core::InputError;
using quasiloc::core::require;
using quasiloc::core::yamlNumber;
using quasiloc::core::yamlNumbers;
using quasiloc::core::yamlText;
using quasiloc::core::yamlTransform;

namespace quasiloc::dataset
{
namespace
{
core::CameraModel camera(const YAML::Node& cam, const std::string& where)
{
    const std::string camera_model = yamlText(cam["camera_model"], where + ".camera_model", "pinhole");
    require(camera_model == "pinhole", where + ".camera_model",
            "'" + camera_model + "' is not supported (pinhole only: pinhole-radtan, pinhole-equidistant)");
    const auto intr = yamlNumbers(cam["intrinsics"], where + ".intrinsics");
    require(intr.size() == 4, where + ".intrinsics", "must hold 4 values [fu fv pu pv]");
    const auto res = yamlNumbers(cam["resolution"], where + ".resolution");
    require(res.size() == 2, where + ".resolution", "must hold 2 values [width height]");
    core::CameraModel m = core::CameraModel::pinhole(int(res[0]), int(res[1]), intr[0], intr[1], intr[2], intr[3]);
    const std::string dist_model = yamlText(cam["distortion_model"], where + ".distortion_model", "none");
    if (dist_model == "radtan")
        m.model = core::DistortionModel::RadTan;
    else if (dist_model == "equidistant")
        m.model = core::DistortionModel::Equidistant;
    else if (dist_model == "none")
        m.model = core::DistortionModel::None;
    else
        throw InputError(where + ".distortion_model",
                         "'" + dist_model + "' is not supported (radtan, equidistant or none)");
    if (m.model != core::DistortionModel::None)
    {
        const auto d = yamlNumbers(cam["distortion_coeffs"], where + ".distortion_coeffs");
        require(d.size() == 4, where + ".distortion_coeffs", "must hold 4 values for " + dist_model);
        for (size_t i = 0; i < 4; ++i) m.dist[i] = d[i];
    }
    m.check(where);
    return m;
}

std::string num(double v)
{
    char buf[40];
    std::snprintf(buf, sizeof(buf), "%.17g", v);
    return buf;
}

std::string matrixText(const mrpt::poses::CPose3D& T)
{
    const auto M = T.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>();
    std::string s;
    for (int r = 0; r < 4; ++r)
        s += "  - [" + num(M(r, 0)) + ", " + num(M(r, 1)) + ", " + num(M(r, 2)) + ", " + num(M(r, 3)) + "]\n";
    return s;
}

std::string cameraText(const core::CameraModel& c, const std::string& topic, const std::string& where)
{
    std::string model = "none";
    if (c.model == core::DistortionModel::RadTan)
    {
        require(c.dist[4] == 0, where, "radtan with k3 != 0 cannot be written as a Kalibr camchain (4 coefficients)");
        model = "radtan";
    }
    else if (c.model == core::DistortionModel::Equidistant)
        model = "equidistant";
    std::string s = "  camera_model: pinhole\n";
    if (c.model != core::DistortionModel::None)
        s += "  distortion_coeffs: [" + num(c.dist[0]) + ", " + num(c.dist[1]) + ", " + num(c.dist[2]) + ", " +
             num(c.dist[3]) + "]\n";
    s += "  distortion_model: " + model + "\n";
    s += "  intrinsics: [" + num(c.fx) + ", " + num(c.fy) + ", " + num(c.cx) + ", " + num(c.cy) + "]\n";
    s += "  resolution: [" + std::to_string(c.width) + ", " + std::to_string(c.height) + "]\n";
    s += "  rostopic: " + topic + "\n";
    return s;
}
}  // namespace

core::StereoRig stereoRigFromKalibr(const std::string& camchain_yaml)
{
    const YAML::Node doc = core::loadYamlFile(camchain_yaml);
    require(doc.IsMap(), camchain_yaml, "not a Kalibr camchain (expected cam0: and cam1: at the top)");
    const std::string cam0 = camchain_yaml + ": cam0", cam1 = camchain_yaml + ": cam1";
    require(doc["cam0"].IsDefined() && doc["cam0"].IsMap(), cam0, "missing or not a map of keys (the left camera)");
    require(doc["cam1"].IsDefined() && doc["cam1"].IsMap(), cam1, "missing or not a map of keys (the right camera)");
    core::StereoRig rig;
    rig.left = camera(doc["cam0"], cam0);
    rig.right = camera(doc["cam1"], cam1);
    const auto T_cam0_imu = yamlTransform(doc["cam0"]["T_cam_imu"], cam0 + ".T_cam_imu");
    rig.T_body_left = -T_cam0_imu;
    if (doc["cam1"]["T_cn_cnm1"])
        rig.T_left_right = -yamlTransform(doc["cam1"]["T_cn_cnm1"], cam1 + ".T_cn_cnm1");
    else
    {
        require(bool(doc["cam1"]["T_cam_imu"]), cam1, "has neither T_cn_cnm1 nor T_cam_imu");
        const auto T_body_right = -yamlTransform(doc["cam1"]["T_cam_imu"], cam1 + ".T_cam_imu");
        rig.T_left_right = T_body_right - rig.T_body_left;  // inverse(T_body_left) * T_body_right
    }
    rig.check(camchain_yaml);
    return rig;
}

ImuCalibration imuCalibrationFromKalibr(const std::string& imu_yaml)
{
    const YAML::Node doc = core::loadYamlFile(imu_yaml);
    require(doc.IsMap(), imu_yaml, "not an IMU YAML (expected a map of keys)");
    const YAML::Node imu_node = doc["imu0"] ? doc["imu0"] : doc;
    require(imu_node.IsMap(), imu_yaml + ": imu0", "not a map of keys");
    const std::string prefix = doc["imu0"] ? imu_yaml + ": imu0." : imu_yaml + ": ";
    const auto value = [&](const char* key) { return yamlNumber(imu_node[key], prefix + key); };
    ImuCalibration imu;
    imu.rate_hz = imu_node["update_rate"] ? value("update_rate") : value("rate_hz");
    imu.gyroscope_noise_density = value("gyroscope_noise_density");
    imu.gyroscope_random_walk = value("gyroscope_random_walk");
    imu.accelerometer_noise_density = value("accelerometer_noise_density");
    imu.accelerometer_random_walk = value("accelerometer_random_walk");
    imu.check(imu_yaml);
    return imu;
}

std::string kalibrCamchainText(const core::StereoRig& rig, const std::string& left_topic,
                               const std::string& right_topic, const std::string& input)
{
    rig.check(input);
    std::string s = "cam0:\n  T_cam_imu:\n" + matrixText(-rig.T_body_left) + "  cam_overlaps: [1]\n";
    s += cameraText(rig.left, left_topic, input + " (left camera)");
    s += "cam1:\n  T_cam_imu:\n" + matrixText(-rig.T_body_right());
    s += "  T_cn_cnm1:\n" + matrixText(-rig.T_left_right) + "  cam_overlaps: [0]\n";
    s += cameraText(rig.right, right_topic, input + " (right camera)");
    return s;
}

std::string kalibrImuText(const ImuCalibration& imu, const std::string& topic)
{
    return "accelerometer_noise_density: " + num(imu.accelerometer_noise_density) +
           "\naccelerometer_random_walk: " + num(imu.accelerometer_random_walk) +
           "\ngyroscope_noise_density: " + num(imu.gyroscope_noise_density) +
           "\ngyroscope_random_walk: " + num(imu.gyroscope_random_walk) + "\nrostopic: " + topic +
           "\nupdate_rate: " + num(imu.rate_hz) + "\n";
}

}  // namespace quasiloc::dataset
