#pragma once
// What quasiloc-track keeps of a run: the estimated and ground-truth trajectories, one diagnostics row per frame,
// and the summary figures it prints.
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/dataset/frame.h>
#include <quasiloc/tracking/tracker.h>
#include <cmath>
#include <optional>
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
    /** A tracked frame; explained_ratio: the geometry check's share (NaN when not checked), ms_check its wall time,
     *  ms_search the relocalization search's on this frame (both counted in the frame's time). */
    void addFrame(const dataset::StereoFrame& frame, const tracking::FrameReport& r, double explained_ratio,
                  double ms_check, double ms_search);

    /** Forgets everything logged at or after time t (starts and frames): a relocalization that finds the track
     *  was wrong re-tracks the frames from its start. */
    void rewindTo(double t);
    /** The logged pose at exactly time t, if any. */
    std::optional<Eigen::Isometry3d> poseAt(double t) const;

    const core::Trajectory& estimate() const { return traj_; }
    const core::Trajectory& groundTruth() const { return gt_traj_; }  ///< at the logged frames that have it
    std::string csv() const;
    double lastErrorM() const { return rows_.empty() ? NAN : rows_.back().error_m; }
    /** The printed summary: frames, losses (withdrawn: the relocalization's fixes confirmed the track;
     *  relocalizations: restarts), ATE against ground truth, time per frame. */
    std::string summary(size_t frames, int losses, int withdrawn, int relocalizations, double longest_unverified_s,
                        double longest_wait_s) const;

   private:
    struct Row
    {
        double t = 0;
        double error_m = NAN;  ///< NaN without ground truth
        double ms = 0;
        bool map_update = false, keyframe = false, lost = false;
        std::string csv;
    };
    core::Trajectory traj_, gt_traj_;
    std::vector<Row> rows_;
};
}  // namespace quasiloc::app
