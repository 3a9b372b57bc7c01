#pragma once
// The track's poses by time (starts and tracked frames), as the session's control needs them: the pose the
// relocalization searches near, and the pose a fix is compared with. A restart at a fix forgets the poses after it
// (those frames are tracked again). The output log is written from the same poses but never read.
#include <Eigen/Geometry>
#include <optional>
#include <quasiloc/core/trajectory_io.h>
#include <vector>

namespace quasiloc::tracking
{
class PoseHistory
{
   public:
    void add(double t, const Eigen::Isometry3d& T_world_cam0);
    /** The pose added last at exactly time t, if any (as the trajectory file holds it). */
    std::optional<Eigen::Isometry3d> at(double t) const;
    /** The length of the path through the positions added at or after time t [m] (0 with fewer than two). */
    double pathLengthSince(double t) const;
    /** The pose added last, if any. */
    std::optional<Eigen::Isometry3d> last() const;
    /** Forgets every pose at or after time t. */
    void forgetFrom(double t);
    /** Poses held: the trajectory's frames so far. */
    size_t size() const { return poses_.size(); }

   private:
    std::vector<core::TimedPose> poses_;
};
}  // namespace quasiloc::tracking
