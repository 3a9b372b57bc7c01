#include <algorithm>
#include <quasiloc/core/pose.h>
#include <quasiloc/tracking/pose_history.h>

namespace quasiloc::tracking
{
void PoseHistory::add(double t, const Eigen::Isometry3d& T_world_cam0)
{
    poses_.push_back({t, core::fromIsometry(T_world_cam0)});
}

std::optional<Eigen::Isometry3d> PoseHistory::at(double t) const
{
    for (auto it = poses_.rbegin(); it != poses_.rend(); ++it)
        if (it->t == t) return core::toIsometry(it->pose);
    return std::nullopt;
}

double PoseHistory::pathLengthSince(double t) const
{
    const auto position = [](const core::TimedPose& p) { return Eigen::Vector3d(p.pose.x(), p.pose.y(), p.pose.z()); };
    double length = 0;
    for (size_t i = poses_.size(); i >= 2 && poses_[i - 2].t >= t; --i)
        length += (position(poses_[i - 1]) - position(poses_[i - 2])).norm();
    return length;
}

std::optional<Eigen::Isometry3d> PoseHistory::last() const
{
    if (poses_.empty()) return std::nullopt;
    return core::toIsometry(poses_.back().pose);
}

void PoseHistory::forgetFrom(double t)
{
    poses_.erase(std::remove_if(poses_.begin(), poses_.end(), [t](const core::TimedPose& p) { return p.t >= t; }),
                 poses_.end());
}
}  // namespace quasiloc::tracking
