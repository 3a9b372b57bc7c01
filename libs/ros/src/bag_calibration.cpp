// The stereo rig from CameraInfo messages and static transforms (bag_calibration.h).
#include <deque>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/ros/bag_calibration.h>
#include <set>

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

void StaticTransforms::add(const TransformMsg& t)
{
    const auto T = core::fromTranslationQuaternion(t.translation, t.rotation.normalized());
    edges_[t.header.frame_id].push_back({t.child_frame_id, T});
    edges_[t.child_frame_id].push_back({t.header.frame_id, -T});
    parent_child_.push_back({t.header.frame_id, t.child_frame_id});
}

std::optional<mrpt::poses::CPose3D> StaticTransforms::lookup(const std::string& from, const std::string& to) const
{
    if (from == to) return mrpt::poses::CPose3D();
    // Breadth first from `from`; T_from_x composed along the way.
    std::map<std::string, mrpt::poses::CPose3D> reached{{from, mrpt::poses::CPose3D()}};
    std::deque<std::string> queue{from};
    while (!queue.empty())
    {
        const std::string frame = queue.front();
        queue.pop_front();
        const auto it = edges_.find(frame);
        if (it == edges_.end()) continue;
        for (const auto& [next, T_frame_next] : it->second)
        {
            if (reached.count(next)) continue;
            reached[next] = reached.at(frame) + T_frame_next;
            if (next == to) return reached[next];
            queue.push_back(next);
        }
    }
    return std::nullopt;
}

std::string StaticTransforms::describe() const
{
    std::string s;
    for (const auto& [p, c] : parent_child_) s += (s.empty() ? "" : ", ") + p + " -> " + c;
    return s.empty() ? "none" : s;
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
