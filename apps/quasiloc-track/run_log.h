#pragma once
// What quasiloc-track keeps of a run: the estimated and ground-truth trajectories, one diagnostics row per frame,
// and the summary figures it prints.
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/dataset/frame.h>
#include <quasiloc/tracking/tracker.h>
#include <sstream>
#include <string>
#include <vector>

namespace quasiloc::app
{
class RunLog
{
   public:
    RunLog();

    /** A start (the first, or a relocalization's): a pose without a tracked frame. */
    void addStart(const dataset::StereoFrame& frame, const Eigen::Isometry3d& T_world_cam0);
    /** A tracked frame; explained_ratio: the geometry check's share (NaN when not checked), ms_check its wall time
     *  (counted in the frame's time). */
    void addFrame(const dataset::StereoFrame& frame, const tracking::FrameReport& r, double explained_ratio,
                  double ms_check);

    const core::Trajectory& estimate() const { return traj_; }
    const core::Trajectory& groundTruth() const { return gt_traj_; }  ///< at the logged frames that have it
    std::string csv() const { return csv_.str(); }
    double lastErrorM() const { return last_error_m_; }
    /** The printed summary: frames, ATE against ground truth, time per frame. */
    std::string summary(size_t frames, int relocalizations, double longest_unverified_s) const;

   private:
    core::Trajectory traj_, gt_traj_;
    std::ostringstream csv_;
    std::vector<double> err_m_, ms_;
    int updates_ = 0, keyframes_ = 0, lost_frames_ = 0;
    double last_error_m_ = NAN;
};
}  // namespace quasiloc::app
