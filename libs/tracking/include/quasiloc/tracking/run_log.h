#pragma once
// What a tracking session keeps of a run: the estimated and ground-truth trajectories, one diagnostics row per frame,
// and the summary figures (printed, and as summary.json). Ground truth is optional: the ATE (through libs/eval, map
// frame, no alignment) is that of the logged poses that have it, i.e. of trajectory.tum as quasiloc-eval scores it
// with association = interpolated; without any, the figures leave the errors out.
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/dataset/frame.h>
#include <quasiloc/tracking/map_context.h>
#include <quasiloc/tracking/tracker.h>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace quasiloc::tracking
{
/** What a session did, beside its RunLog. */
struct SessionSummary
{
    size_t frames = 0;
    int losses = 0;                   ///< loss declared (rejected alignments or failed geometry checks)
    int withdrawn = 0;                ///< losses whose fix confirmed the track
    int relocalizations = 0;          ///< restarts at a fix
    double longest_unverified_s = 0;  ///< from a confirmed pose to the relocalization that followed a loss
    double longest_wait_s = 0;        ///< ... and to when its fix was found (replay time)
    Eigen::Isometry3d T_world_cam0_start = Eigen::Isometry3d::Identity();
    std::optional<Eigen::Isometry3d> T_world_cam0_start_truth;  ///< the start frame's ground truth, if any
    std::optional<double> t_first_frame;  ///< the first frame read (a global start may come frames later)
    double start_search_s = 0;            ///< init = global: wall time until the start was found
    MapBuildFigures map;                  ///< loading the map and building from it
    double localizer_setup_s = 0;         ///< the global localizer's set-up (distance field and candidates)
};

class RunLog
{
   public:
    RunLog();

    /** A start (the first, or a relocalization's): a pose without a tracked frame. */
    void addStart(const dataset::StereoFrame& frame, const Eigen::Isometry3d& T_world_cam0);
    /** A tracked frame; explained_ratio: the geometry check's share (NaN when not checked), ms_check its wall time,
     *  ms_search the relocalization search's on this frame (both counted in the frame's time). */
    void addFrame(const dataset::StereoFrame& frame, const FrameReport& r, double explained_ratio, double ms_check,
                  double ms_search);

    /** Forgets everything logged at or after time t (starts and frames): a relocalization that finds the track
     *  was wrong re-tracks the frames from its start. */
    void rewindTo(double t);
    /** Flags the tracked frames with after_t < t <= up_to_t as unverified (the diagnostics' `unverified` column):
     *  the session decides which stretches (tracking_session.h). */
    void markUnverified(double after_t, double up_to_t);
    /** The logged pose at exactly time t, if any. */
    std::optional<Eigen::Isometry3d> poseAt(double t) const;

    const core::Trajectory& estimate() const { return traj_; }
    const core::Trajectory& groundTruth() const { return gt_traj_; }  ///< at the logged poses that have it
    /** Whether any logged pose (a start or a frame) has ground truth: else there is no error to report. */
    bool hasGroundTruth() const { return !gt_traj_.poses.empty(); }
    std::string csv() const;
    double lastErrorM() const { return rows_.empty() ? NAN : rows_.back().error_m; }
    /** The printed summary: frames, losses (withdrawn: the relocalization's fixes confirmed the track;
     *  relocalizations: restarts), ATE against ground truth (no line when hasGroundTruth() is false: the program
     *  says why), time per frame. */
    std::string summary(const SessionSummary& session) const;
    /** The same figures as JSON (summary.json), for scripts and tests; without ground truth, no "ate" object and no
     *  start error (omitted, not null). */
    std::string summaryJson(const SessionSummary& session) const;

   private:
    /** The figures both summaries report (run_log.cpp). */
    struct Figures;
    Figures figures() const;

    /** One tracked frame. */
    struct Row
    {
        double t = 0;
        double error_m = NAN;  ///< NaN without ground truth
        double ms = 0;
        bool map_update = false, keyframe = false, lost = false, unverified = false;
        std::string csv;  ///< without the unverified column, decided later
    };
    core::Trajectory traj_, gt_traj_;
    std::vector<Row> rows_;
};
}  // namespace quasiloc::tracking
