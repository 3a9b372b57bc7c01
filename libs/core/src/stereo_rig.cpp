#include <mrpt/config/CConfigFile.h>

#include <Eigen/Core>

#include <filesystem>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/core/yaml_read.h>

namespace quasiloc::core
{
namespace
{
std::vector<double> poseToVector(const mrpt::poses::CPose3D& T)
{
    const Eigen::Quaterniond q = quaternionOf(T);
    return {T.x(), T.y(), T.z(), q.w(), q.x(), q.y(), q.z()};
}

mrpt::poses::CPose3D poseFromIni(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
                                 const std::string& key)
{
    const std::string input = "INI [" + section + "] " + key;
    std::vector<double> v;
    cfg.read_vector(section, key, std::vector<double>(), v, false);
    require(v.size() == 7, input, "expected [x y z qw qx qy qz] (7 values), got " + std::to_string(v.size()));
    const Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
    require(std::abs(q.norm() - 1.0) < 1e-3, input, "quaternion is not unit length");
    const auto T = fromTranslationQuaternion({v[0], v[1], v[2]}, q);
    checkFinite(T, input);
    return T;
}

std::string vectorToString(const std::vector<double>& v)
{
    std::string s = "[";
    char buf[64];
    for (size_t i = 0; i < v.size(); ++i)
    {
        std::snprintf(buf, sizeof(buf), "%s%.12g", i ? " " : "", v[i]);
        s += buf;
    }
    return s + "]";
}
}  // namespace

void StereoRectification::rectify(const cv::Mat& left_raw, const cv::Mat& right_raw, cv::Mat& left_rect,
                                  cv::Mat& right_rect) const
{
    cv::remap(left_raw, left_rect, fixed_left_xy, fixed_left_frac, cv::INTER_LINEAR);
    cv::remap(right_raw, right_rect, fixed_right_xy, fixed_right_frac, cv::INTER_LINEAR);
}

StereoRectification StereoRig::rectify(double alpha) const
{
    check("stereo rig");
    require(left.model == right.model, "stereo rig", "both cameras must use the same distortion model");
    // OpenCV wants (R, T) mapping left-camera points to the right camera: the inverse of T_left_right.
    const mrpt::poses::CPose3D T_right_left = -T_left_right;
    cv::Mat R, T;
    cv::eigen2cv(Eigen::Matrix3d(T_right_left.getRotationMatrix().asEigen()), R);
    cv::eigen2cv(Eigen::Vector3d(T_right_left.x(), T_right_left.y(), T_right_left.z()), T);
    const cv::Size size(left.width, left.height);
    StereoRectification out;
    cv::Mat R1, R2, P1, P2, Q;
    const cv::Mat K1(left.K()), K2(right.K());
    if (left.model == DistortionModel::Equidistant)
    {
        cv::fisheye::stereoRectify(K1, left.distCoeffs(), K2, right.distCoeffs(), size, R, T, R1, R2, P1, P2, Q,
                                   cv::CALIB_ZERO_DISPARITY, size, alpha);
        cv::fisheye::initUndistortRectifyMap(K1, left.distCoeffs(), R1, P1, size, CV_32FC1, out.map_left_x,
                                             out.map_left_y);
        cv::fisheye::initUndistortRectifyMap(K2, right.distCoeffs(), R2, P2, size, CV_32FC1, out.map_right_x,
                                             out.map_right_y);
    }
    else
    {
        cv::stereoRectify(K1, left.distCoeffs(), K2, right.distCoeffs(), size, R, T, R1, R2, P1, P2, Q,
                          cv::CALIB_ZERO_DISPARITY, alpha, size);
        cv::initUndistortRectifyMap(K1, left.distCoeffs(), R1, P1, size, CV_32FC1, out.map_left_x, out.map_left_y);
        cv::initUndistortRectifyMap(K2, right.distCoeffs(), R2, P2, size, CV_32FC1, out.map_right_x, out.map_right_y);
    }
    cv::convertMaps(out.map_left_x, out.map_left_y, out.fixed_left_xy, out.fixed_left_frac, CV_16SC2);
    cv::convertMaps(out.map_right_x, out.map_right_y, out.fixed_right_xy, out.fixed_right_frac, CV_16SC2);
    out.R_left = cv::Matx33d(R1);
    out.R_right = cv::Matx33d(R2);
    out.P_left = cv::Matx34d(P1);
    out.P_right = cv::Matx34d(P2);
    out.Q = cv::Matx44d(Q);
    out.rectified_left = CameraModel::pinhole(left.width, left.height, out.P_left(0, 0), out.P_left(1, 1),
                                              out.P_left(0, 2), out.P_left(1, 2));
    out.baseline_m = -out.P_right(0, 3) / out.P_right(0, 0);
    return out;
}

void StereoRig::check(const std::string& input) const
{
    left.check(input + " (left camera)");
    right.check(input + " (right camera)");
    checkFinite(T_left_right, input + " (T_left_right)");
    checkFinite(T_body_left, input + " (T_body_left)");
    require(baseline() > 1e-4, input, "stereo baseline is zero: T_left_right has no translation");
}

StereoRig StereoRig::loadFromIni(const mrpt::config::CConfigFileBase& cfg, const std::string& prefix)
{
    StereoRig rig;
    rig.left = CameraModel::loadFromIni(cfg, prefix + "left");
    rig.right = CameraModel::loadFromIni(cfg, prefix + "right");
    const std::string rig_section = prefix + "rig";
    require(cfg.sectionExists(rig_section), "INI section [" + rig_section + "]",
            "section is missing (T_left_right and T_body_left expected)");
    rig.T_left_right = poseFromIni(cfg, rig_section, "T_left_right");
    rig.T_body_left = poseFromIni(cfg, rig_section, "T_body_left");
    rig.check("INI sections [" + prefix + "left/right/rig]");
    return rig;
}

void StereoRig::saveToIni(mrpt::config::CConfigFileBase& cfg, const std::string& prefix) const
{
    left.saveToIni(cfg, prefix + "left");
    right.saveToIni(cfg, prefix + "right");
    cfg.write(prefix + "rig", "T_left_right", vectorToString(poseToVector(T_left_right)));
    cfg.write(prefix + "rig", "T_body_left", vectorToString(poseToVector(T_body_left)));
}

mrpt::poses::CPose3D readEurocSensorPose(const std::string& yaml_path)
{
    const YAML::Node doc = loadYamlMap(yaml_path, "sensor.yaml");
    return yamlTransform(doc["T_BS"], yaml_path + ": T_BS");
}

StereoRig StereoRig::fromEuroc(const std::string& cam0_yaml, const std::string& cam1_yaml)
{
    StereoRig rig;
    rig.left = CameraModel::fromEurocYaml(cam0_yaml);
    rig.right = CameraModel::fromEurocYaml(cam1_yaml);
    rig.T_body_left = readEurocSensorPose(cam0_yaml);
    const auto T_body_right = readEurocSensorPose(cam1_yaml);
    rig.T_left_right = T_body_right - rig.T_body_left;  // inverse(T_body_left) * T_body_right
    rig.check(cam0_yaml + " + " + cam1_yaml);
    return rig;
}

}  // namespace quasiloc::core
