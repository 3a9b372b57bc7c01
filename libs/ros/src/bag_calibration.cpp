// The stereo rig from CameraInfo messages and static transforms (bag_calibration.h).
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/ros/bag_calibration.h>

using quasiloc::core::InputError;
using quasiloc::core::require;

namespace quasiloc::ros
{
core::CameraModel cameraModelFromCameraInfo(const CameraInfoMsg& info, const std::string& where)
{
    core::CameraModel cam;
    cam.width = int(std::min<std::uint32_t>(info.width, 1u << 16));
    cam.height = int(std::min<std::uint32_t>(info.height, 1u << 16));
    cam.fx = info.k[0];
    cam.fy = info.k[4];
    cam.cx = info.k[2];
    cam.cy = info.k[5];
    const std::string& model = info.distortion_model;
    const auto& d = info.d;
    if (model == "plumb_bob" || (model.empty() && d.empty()))
    {
        require(d.empty() || d.size() == 4 || d.size() == 5, where,
                "distortion model plumb_bob with " + std::to_string(d.size()) + " coefficients (4 or 5)");
        cam.model = d.empty() ? core::DistortionModel::None : core::DistortionModel::RadTan;
        for (std::size_t i = 0; i < d.size(); ++i) cam.dist[i] = d[i];
    }
    else if (model == "equidistant" || model == "fisheye" || model == "kannala_brandt")
    {
        require(d.size() == 4, where,
                "distortion model " + model + " with " + std::to_string(d.size()) + " coefficients (4)");
        cam.model = core::DistortionModel::Equidistant;
        for (std::size_t i = 0; i < 4; ++i) cam.dist[i] = d[i];
    }
    else
        throw InputError(where, "CameraInfo distortion model '" + model +
                                    "' is not supported (plumb_bob or equidistant; or give a Kalibr camchain)");
    cam.check(where);
    return cam;
}

core::StereoRig stereoRigFromBag(const BagCalibrationInput& in)
{
    core::StereoRig rig;
    rig.left = cameraModelFromCameraInfo(in.left, in.left_where);
    rig.right = cameraModelFromCameraInfo(in.right, in.right_where);
    const std::string& left_frame = in.left.header.frame_id;
    const std::string& right_frame = in.right.header.frame_id;
    require(!left_frame.empty(), in.left_where, "CameraInfo without a frame_id: the extrinsics cannot be found");
    require(!right_frame.empty(), in.right_where, "CameraInfo without a frame_id: the extrinsics cannot be found");
    require(left_frame != right_frame, in.right_where,
            "both cameras have frame_id '" + left_frame + "': the stereo baseline cannot be found");
    const auto T_body_left = in.tf.lookup(in.imu_frame, left_frame);
    require(T_body_left.has_value(), in.tf_where,
            "no chain of static transforms from the IMU frame '" + in.imu_frame + "' to the left camera frame '" +
                left_frame + "' (transforms there: " + in.tf.describe() + ")");
    const auto T_left_right = in.tf.lookup(left_frame, right_frame);
    require(T_left_right.has_value(), in.tf_where,
            "no chain of static transforms from the left camera frame '" + left_frame + "' to the right one '" +
                right_frame + "' (transforms there: " + in.tf.describe() + ")");
    rig.T_body_left = *T_body_left;
    rig.T_left_right = *T_left_right;
    rig.check(in.tf_where);
    return rig;
}

}  // namespace quasiloc::ros
