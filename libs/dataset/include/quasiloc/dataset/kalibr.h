#pragma once
// Kalibr calibrations: a camchain YAML (the stereo rig) and an IMU YAML (the noise model), read into the
// calibration INI's types (calibration.h), and written back for data we export (rawlog2bag).
//
// camchain: cam0 is the left camera, cam1 the right one. Each has camera_model (pinhole), intrinsics
// [fu fv pu pv], resolution [w h], distortion_model (radtan | equidistant | none) with distortion_coeffs, and
// T_cam_imu (4x4, maps IMU-frame points into the camera frame). cam1's T_cn_cnm1 (maps cam0 points into cam1)
// gives T_left_right when present; otherwise it follows from both T_cam_imu. The body frame is the IMU frame.
// IMU YAML: Kalibr's imu.yaml (flat keys, update_rate) or a Kalibr result / EuRoC sensor.yaml (under imu0:, or
// rate_hz); the four noise densities are required. The bias is not in these files: it stays unknown.
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/dataset/calibration.h>
#include <string>

namespace quasiloc::dataset
{
/** InputError naming the file and the camera/key for a missing file, a missing or malformed value, an
 *  unsupported camera or distortion model. */
core::StereoRig stereoRigFromKalibr(const std::string& camchain_yaml);

/** InputError naming the file and the key for a missing or non-positive value. */
ImuCalibration imuCalibrationFromKalibr(const std::string& imu_yaml);

/** The camchain YAML of `rig` (full double precision). radtan needs k3 = 0 (Kalibr has no k3): InputError
 *  naming `input` otherwise. */
std::string kalibrCamchainText(const core::StereoRig& rig, const std::string& left_topic,
                               const std::string& right_topic, const std::string& input);
/** Kalibr's imu.yaml for `imu` (noise model and rate). */
std::string kalibrImuText(const ImuCalibration& imu, const std::string& topic);

}  // namespace quasiloc::dataset
