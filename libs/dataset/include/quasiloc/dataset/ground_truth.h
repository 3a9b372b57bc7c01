#pragma once
// Ground-truth trajectories of cam0 (T_world_cam0) and the per-frame lookup.
#include <mrpt/poses/CPose3D.h>

#include <optional>
#include <quasiloc/core/trajectory_io.h>
#include <string>

namespace quasiloc::dataset
{
struct GroundTruthFile
{
    enum class Kind
    {
        TumCam0,   ///< TUM file "t x y z qx qy qz qw" of T_world_cam0: taken as is
        EurocBody  ///< EuRoC state_groundtruth_estimate0/data.csv of T_world_body: multiplied by T_body_cam0
    };
    Kind kind = Kind::TumCam0;
    core::Trajectory T_world_cam0;      ///< sorted by time, one pose per timestamp; header "T_world_cam0 ..."
    size_t duplicate_rows_dropped = 0;  ///< rows repeating an earlier timestamp (the first one is kept)
};

/** Reads a ground-truth file, deciding its kind by content: comma-separated rows whose first field is an
 *  integer nanosecond timestamp and which have at least 8 fields (t, p_xyz, q_wxyz, ...) are EuRoC body
 *  poses; anything else must be a TUM file (core::readTum). InputError naming the file (and line). */
GroundTruthFile readGroundTruthCam0(const std::string& path, const mrpt::poses::CPose3D& T_body_cam0);

/** The poses with t0 - margin_s <= t <= t1 + margin_s. */
core::Trajectory restrictToSpan(const core::Trajectory& traj, double t0, double t1, double margin_s);

/** The pose at time t: interpolated between the two samples around t (slerp) when the nearer one is within
 *  max_dt_s; outside the trajectory, the end sample when it is within max_dt_s; otherwise nothing. Never
 *  extrapolates: frames before ground truth begins get no pose. */
std::optional<mrpt::poses::CPose3D> poseAt(const core::Trajectory& traj, double t, double max_dt_s);

}  // namespace quasiloc::dataset
