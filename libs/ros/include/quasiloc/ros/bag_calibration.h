#pragma once
// The stereo rig from a bag when no Kalibr camchain is given: each camera's intrinsics from its
// sensor_msgs/CameraInfo (K and D of the raw image; R and P, the rectification, are not used), the extrinsics from
// the static transforms (tf2_msgs/TFMessage on /tf_static): T_body_left = the pose of the left camera's frame in the
// IMU's frame, T_left_right = the right camera's frame in the left's, each through any chain of transforms.
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/ros/messages.h>
#include <quasiloc/ros/static_transforms.h>
#include <string>

namespace quasiloc::ros
{
/** The camera of a CameraInfo: "plumb_bob" (k1 k2 p1 p2 [k3]) is radtan, "equidistant" (k1 k2 k3 k4) is
 *  equidistant; any other model (rational_polynomial, ...), a zero focal length or size is an InputError naming
 *  `where` (file and topic) and the model. */
core::CameraModel cameraModelFromCameraInfo(const CameraInfoMsg& info, const std::string& where);

struct BagCalibrationInput
{
    CameraInfoMsg left, right;
    std::string left_where, right_where;  ///< "<bag> topic <camera_info topic>"
    StaticTransforms tf;
    std::string tf_where;  ///< "<bag> topic /tf_static"
    std::string imu_frame;
};

/** InputError naming the topic for an unsupported camera, and the tf topic with the frames when a transform is
 *  missing. */
core::StereoRig stereoRigFromBag(const BagCalibrationInput& in);

}  // namespace quasiloc::ros
