#pragma once
// The track monitor: the track's health as an explicit state, moved by events, and everything the session's policy
// decides from it. It sees no image: it is driven by the tracker's frame reports, the loss check's results, the
// relocalization's fixes and the input's faults, and it is unit-tested from tables of such events.
//
//   health        Verified -> Doubted        a check failed, the stereo was left out, or the stereo drifts from the
//                                            map (stereo_drift_ratio times its usual distance; the edge pose still
//                                            trusted)
//                 Verified/Doubted
//                          -> EdgesSuspect   an input fault, or a keyframe whose map alignment was rejected: the
//                                            edge-aligned pose may be the wrong one
//                 any      -> Verified       a check passed (in Restarted: on a frame whose edges fit as usual)
//                 any      -> Lost           lost_after_failed_checks failed checks, or lost_after_misses rejected
//                                            map alignments, in a row, or a restart unconfirmed after
//                                            lost_unconfirmed_restart_s: a relocalization search begins
//                 Lost     -> (as before)    a fix agrees with the track: the loss is withdrawn
//                 Lost     -> Restarted      a fix disagrees: the tracker restarts at it
//   stereo gate   the bound the next frame's stereo is gated with (stereo_gate.h): stereo_check_max_sigmas while
//                 the edge pose is trusted; stereo_check_release_sigmas while the stereo is held (rejected within
//                 stereo_check_hold_s); none when the edge pose is suspect or an input fault is pending (after a
//                 gap or a restart the stereo is what brings the track back), nor while Lost with
//                 odometry_while_lost (the map terms are off then, and the stereo landmarks keep the track, the
//                 search's prior, near the truth).
//   loss check    due every check_every frames, and on every frame while the track is unverified or a check has
//                 failed; not while Lost or while the stereo is held (the check weighs the same stereo), unless the
//                 hold has lasted stereo_hold_max_s (every rejected frame renews a hold, and a track drifting under
//                 it would go unchecked): then a passed check releases the stereo and failed ones lose the track.
//                 It aligns the stereo to the map when too little of it is explained, and always while it drifts.
//                 With stereo_hold_fit_below it also runs on a hold's first frame: a rejected stereo that fits the map
//                 near the tracked pose is sound (the pose is what disagrees), so it is released, not gated for
//                 stereo_check_hold_s, and the check judges the pose; one that fits nowhere stays held.
//   velocity      while Lost the gate asks the tracker to widen its velocity's uncertainty
//                 (lost_velocity_random_walk): a lost track's velocity may have diverged.
//   unverified    the stretches of the track no check confirmed, handed to the log as they close: from an input
//                 fault, a missed map update, a held stereo or a restart to the next passed check; from the last
//                 confirmed pose to a failed check's pass or to the fix that ended a loss (or to the end).
// Thresholds: [TrackMonitor] (TrackMonitorOptions).
#include <functional>
#include <optional>
#include <ostream>
#include <quasiloc/tracking/frame_report.h>
#include <quasiloc/tracking/stereo_gate.h>
#include <quasiloc/tracking/tracking_options.h>

namespace quasiloc::tracking
{
enum class TrackHealth
{
    Verified,      ///< the last check passed (or the track just started): the edge pose gates the stereo
    Doubted,       ///< unverified with the edge pose trusted: a check failed, or the stereo was held
    EdgesSuspect,  ///< the edge-aligned pose may be the wrong one (an input fault, a missed map update)
    Restarted,     ///< restarted at a fix: unverified until a check passes on a frame whose edges fit as usual
    Lost           ///< a relocalization search is under way while the track goes on
};
const char* toString(TrackHealth h);

/** What the stereo geometry of a checked frame says of the tracked pose (GlobalStarter::checkTrack). */
struct CheckResult
{
    double explained = 0;          ///< share of the stereo points the map explains at the tracked pose
    bool refined = false;          ///< the points were also aligned to the map from the tracked pose
    double refined_explained = 0;  ///< that share at the aligned pose
};

enum class CheckOutcome
{
    Passed,             ///< the pose is confirmed
    PassedUnconfirmed,  ///< passed, but after a restart the frame's edges fit worse than usual: not confirmed
    Failed,             ///< the stereo fits the map better elsewhere, or too little of it is explained
    StereoHeld          ///< the stereo the gate rejected fits the map nowhere near: it is held, the pose not judged
};
const char* toString(CheckOutcome o);

class TrackMonitor
{
   public:
    /** Called with each unverified stretch (after_t, up_to_t] as it closes. */
    using UnverifiedSink = std::function<void(double after_t, double up_to_t)>;

    /** `console` (the stereo gate's messages) must outlive the monitor. InputError for bad options. */
    TrackMonitor(const TrackMonitorOptions& options, std::ostream& console, UnverifiedSink unverified);

    // Events, in the order a frame meets them.
    /** The track starts at time t, verified. */
    void started(double t);
    /** The frame of time t was read right after an input fault (rejected frames, a gap between frames or in the IMU
     *  longer than input_gap_s): the track is suspect from that frame on. */
    void inputFault(double t);
    /** The tracker's result on a frame. */
    void frameTracked(const FrameReport& r);
    /** The loss check's result on frame r (checked because checkDue). */
    CheckOutcome checked(const FrameReport& r, const CheckResult& c);
    /** A relocalization search begins (after lossDue). */
    void searchBegun();
    /** The search found a fix at t_fix: it agrees with the track (the loss is withdrawn), or the track restarts. */
    void fixFound(double t_fix, bool agrees_with_track);
    /** The frames have ended. */
    void ended();

    // What the policy decides.
    TrackHealth health() const { return health_; }
    /** The gate of the next frame's stereo. */
    StereoGate stereoGate() const;
    /** Frame number n (counted from the start) is to be checked. */
    bool checkDue(size_t n) const;
    /** The check aligns the stereo to the map when less than this share of it is explained. */
    double checkAlignsBelow() const;
    /** The track is lost after frame r: a search is to begin. */
    bool lossDue(const FrameReport& r) const;
    /** Frame r's map alignments have been rejected lost_after_misses times in a row (the diagnostics' `lost`). */
    bool lostByMisses(const FrameReport& r) const;
    /** The latest pose a check or a fix confirmed. */
    double lastVerifiedT() const { return last_verified_t_; }
    /** The frame's edges fit as well as they usually do (edge inlier ratio against the running mean). */
    bool edgesAsUsual(const FrameReport& r) const;

   private:
    /** The edge-aligned pose is trusted (Lost: as it was when the search began). */
    bool edgesTrusted() const;
    /** The edge pose becomes suspect (in Lost: the state a withdrawn loss returns to). */
    void edgesBecomeSuspect();
    /** The track is unverified after after_t until a check passes or a fix settles a loss. */
    void flagUnverified(double after_t);
    void closeUnverified(double up_to_t);
    void holdStereo(const FrameReport& r);
    void releaseStereo();
    /** The first check of a hold: false when the held stereo fits the map nowhere near (then it stays held). */
    bool judgeHeldStereo(const FrameReport& r, const CheckResult& c);
    /** Frame r's stereo lies farther from the map than usual: unverified, and checks align until one passes. */
    void watchStereoDrift(const FrameReport& r);
    /** The running means of the edge fit and the stereo's distance to the map, over frames that agree. */
    void updateUsualFit(const FrameReport& r);

    TrackMonitorOptions options_;
    std::ostream& out_;
    UnverifiedSink unverified_;
    TrackHealth health_ = TrackHealth::Verified;
    TrackHealth before_loss_ = TrackHealth::Verified;  ///< Lost: what a withdrawn loss returns to
    std::optional<double> unverified_after_;           ///< the open unverified stretch
    std::optional<double> input_fault_t_;              ///< the frame read after an input fault, until it is tracked
    std::optional<double> stereo_held_until_;          ///< the stereo was left out: held until then
    std::optional<double> stereo_held_since_;          ///< the first rejected frame of the hold
    bool hold_overlong_ = false;                       ///< the hold has lasted stereo_hold_max_s: checks are due
    bool hold_judged_ = true;                          ///< a check has weighed whether the held stereo fits the map
    std::optional<double> stereo_vouched_until_;       ///< a check found the rejected stereo sound: ungated until
    double last_verified_t_ = 0;
    double restarted_at_t_ = 0;  ///< the fix the track restarted at (Restarted)
    int failed_checks_ = 0;      ///< in a row
    double usual_edge_ratio_ = NAN;
    double usual_stereo_sigmas_ = NAN;
    bool stereo_drifts_ = false;  ///< until a check passes
};
}  // namespace quasiloc::tracking
