#pragma once
// A calibrated stereo pair with an IMU ("body") frame: the cameras and the rigid transforms between them.
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/poses/CPose3D.h>

#include <opencv2/core.hpp>
#include <quasiloc/core/camera_model.h>
#include <string>

namespace quasiloc::core
{
/** What OpenCV's stereoRectify gives, plus the undistort-rectify maps of both images. */
struct StereoRectification
{
    cv::Matx33d R_left, R_right;  ///< rotation from the raw to the rectified camera frame
    cv::Matx34d P_left, P_right;  ///< projection matrices of the rectified cameras
    cv::Matx44d Q;                ///< disparity-to-depth matrix
    CameraModel rectified_left;   ///< ideal pinhole of the rectified left camera
    double baseline_m = 0;
    cv::Mat map_left_x, map_left_y, map_right_x, map_right_y;  ///< for cv::remap, CV_32FC1
    /** The same maps in OpenCV's fixed-point form (cv::convertMaps: CV_16SC2 and CV_16UC1), what cv::remap turns
     *  float maps into for every call anyway: rectify() uses these, with the same result. */
    cv::Mat fixed_left_xy, fixed_left_frac, fixed_right_xy, fixed_right_frac;

    /** Both images through their maps (bilinear). */
    void rectify(const cv::Mat& left_raw, const cv::Mat& right_raw, cv::Mat& left_rect, cv::Mat& right_rect) const;
};

class StereoRig
{
   public:
    CameraModel left, right;
    mrpt::poses::CPose3D T_left_right;  ///< pose of the right camera in the left camera frame
    mrpt::poses::CPose3D T_body_left;   ///< pose of the left camera in the body (IMU) frame

    double baseline() const { return T_left_right.translation().norm(); }
    mrpt::poses::CPose3D T_body_right() const { return T_body_left + T_left_right; }

    /** Rectification with OpenCV (radtan: cv::stereoRectify; equidistant: cv::fisheye::stereoRectify).
     *  alpha = 0 keeps only valid pixels, 1 keeps all source pixels. */
    StereoRectification rectify(double alpha = 0.0) const;

    void check(const std::string& input) const;

    /** INI layout: sections <prefix>left and <prefix>right (CameraModel keys), and in <prefix>rig:
     *  T_left_right=[x y z qw qx qy qz], T_body_left=[x y z qw qx qy qz]. */
    static StereoRig loadFromIni(const mrpt::config::CConfigFileBase& cfg, const std::string& prefix = "camera_");
    void saveToIni(mrpt::config::CConfigFileBase& cfg, const std::string& prefix = "camera_") const;

    /** Two EuRoC sensor.yaml files (cam0 = left, cam1 = right); the body frame is the IMU frame. */
    static StereoRig fromEuroc(const std::string& cam0_yaml, const std::string& cam1_yaml);
};

/** T_BS of an EuRoC sensor.yaml: the pose of the sensor in the body frame. */
mrpt::poses::CPose3D readEurocSensorPose(const std::string& yaml_path);

}  // namespace quasiloc::core
