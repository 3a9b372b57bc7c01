#include <quasiloc/tracking/track_monitor.h>

#include <algorithm>
#include <iomanip>

namespace quasiloc::tracking
{
const char* toString(TrackHealth h)
{
    switch (h)
    {
        case TrackHealth::Verified: return "verified";
        case TrackHealth::Doubted: return "doubted";
        case TrackHealth::EdgesSuspect: return "edges suspect";
        case TrackHealth::Restarted: return "restarted";
        case TrackHealth::Lost: return "lost";
    }
    return "?";
}

const char* toString(CheckOutcome o)
{
    switch (o)
    {
        case CheckOutcome::Passed: return "passed";
        case CheckOutcome::PassedUnconfirmed: return "passed, not confirming the restart (edges poorer than usual)";
        case CheckOutcome::Failed: return "failed";
        case CheckOutcome::StereoHeld: return "not judged: the stereo fits the map nowhere near, it stays held";
    }
    return "?";
}

TrackMonitor::TrackMonitor(const TrackMonitorOptions& options, std::ostream& console, UnverifiedSink unverified)
    : options_(options), out_(console), unverified_(std::move(unverified))
{
    options_.check("TrackMonitor");
}

void TrackMonitor::started(double t)
{
    health_ = TrackHealth::Verified;
    last_verified_t_ = t;
}

void TrackMonitor::inputFault(double t) { input_fault_t_ = t; }

bool TrackMonitor::edgesTrusted() const
{
    const TrackHealth h = health_ == TrackHealth::Lost ? before_loss_ : health_;
    return h == TrackHealth::Verified || h == TrackHealth::Doubted;
}

void TrackMonitor::edgesBecomeSuspect()
{
    TrackHealth& h = health_ == TrackHealth::Lost ? before_loss_ : health_;
    if (h != TrackHealth::Restarted) h = TrackHealth::EdgesSuspect;
}

void TrackMonitor::flagUnverified(double after_t)
{
    if (!unverified_after_ || after_t < *unverified_after_) unverified_after_ = after_t;
    if (health_ == TrackHealth::Verified) health_ = TrackHealth::Doubted;
}

void TrackMonitor::closeUnverified(double up_to_t)
{
    if (!unverified_after_) return;
    unverified_(*unverified_after_, up_to_t);
    unverified_after_.reset();
    if (health_ == TrackHealth::Doubted) health_ = TrackHealth::Verified;
}

bool TrackMonitor::edgesAsUsual(const FrameReport& r) const
{
    return std::isnan(usual_edge_ratio_) ||
           r.edge_inlier_ratio >= options_.stereo_check_min_edge_ratio * usual_edge_ratio_;
}

StereoGate TrackMonitor::stereoGate() const
{
    StereoGate g;
    g.min_edge_ratio = options_.stereo_check_min_edge_ratio;
    g.usual_edge_ratio = usual_edge_ratio_;
    // Lost, tracked by odometry: the search's prior is the track's position, which the stereo landmarks keep near
    // the truth; the tracked pose the stereo would be measured against is the doubtful part.
    const bool odometry = options_.odometry_while_lost && health_ == TrackHealth::Lost;
    g.map_terms = !odometry;
    if (health_ == TrackHealth::Lost) g.velocity_random_walk = options_.lost_velocity_random_walk;
    if (options_.stereo_check_max_sigmas <= 0 || odometry || stereo_vouched_until_) return g;
    if (stereo_held_until_)
        g.max_sigmas = options_.stereo_check_release_sigmas;
    else if (edgesTrusted() && !input_fault_t_)
        g.max_sigmas = options_.stereo_check_max_sigmas;
    return g;
}

void TrackMonitor::holdStereo(const FrameReport& r)
{
    if (r.stereo_rejected)
    {
        if (!stereo_held_until_)
        {
            out_ << "stereo check at t " << std::fixed << std::setprecision(3) << r.t << ": the stereo points lie "
                 << std::setprecision(1) << r.stereo_map_sigmas
                 << " sigmas from the map (median): stereo left out, frames unverified (a left/right desync or a "
                    "broken calibration?)"
                 << std::endl;
            stereo_held_since_ = r.t;
            hold_judged_ = options_.stereo_hold_fit_below <= 0;
        }
        stereo_held_until_ = r.t + options_.stereo_check_hold_s;
    }
    else if (stereo_held_until_ && r.t >= *stereo_held_until_)
    {
        out_ << "stereo check at t " << std::fixed << std::setprecision(3) << r.t << ": the stereo has agreed with "
             << "the map for " << std::setprecision(1) << options_.stereo_check_hold_s << " s" << std::endl;
        releaseStereo();
    }
    if (stereo_held_until_) flagUnverified(r.t - 1e-6);
    if (stereo_held_until_ && !hold_overlong_ && options_.stereo_hold_max_s > 0 &&
        r.t - *stereo_held_since_ >= options_.stereo_hold_max_s)
    {
        hold_overlong_ = true;
        out_ << "stereo check at t " << std::fixed << std::setprecision(3) << r.t << ": the stereo has been held for "
             << std::setprecision(1) << r.t - *stereo_held_since_
             << " s: the pose is checked on every frame until a check confirms it or the track is lost" << std::endl;
    }
}

void TrackMonitor::releaseStereo()
{
    stereo_held_until_.reset();
    stereo_held_since_.reset();
    hold_overlong_ = false;
}

void TrackMonitor::frameTracked(const FrameReport& r)
{
    if (stereo_vouched_until_ && r.t >= *stereo_vouched_until_) stereo_vouched_until_.reset();
    if (input_fault_t_ && r.t >= *input_fault_t_)
    {
        flagUnverified(r.t - 1e-6);
        input_fault_t_.reset();
        edgesBecomeSuspect();
    }
    if (r.keyframe && !r.map_update)
    {
        flagUnverified(r.t - 1e-6);
        edgesBecomeSuspect();
    }
    holdStereo(r);
    watchStereoDrift(r);
    updateUsualFit(r);
}

void TrackMonitor::watchStereoDrift(const FrameReport& r)
{
    if (options_.stereo_drift_ratio <= 0 || std::isnan(r.stereo_map_sigmas) || std::isnan(usual_stereo_sigmas_) ||
        r.stereo_rejected || r.stereo_map_sigmas <= options_.stereo_drift_ratio * usual_stereo_sigmas_)
        return;
    if (!stereo_drifts_)
        out_ << "stereo check at t " << std::fixed << std::setprecision(3) << r.t << ": the stereo points lie "
             << std::setprecision(1) << r.stereo_map_sigmas << " sigmas from the map (usually " << usual_stereo_sigmas_
             << "): frames unverified until a check confirms the pose" << std::endl;
    stereo_drifts_ = true;
    flagUnverified(r.t - 1e-6);
}

void TrackMonitor::updateUsualFit(const FrameReport& r)
{
    // Over the frames whose stereo was measured and agreed with the map at an edge pose that fit as usual, while
    // no drift is suspected.
    if (std::isnan(r.stereo_map_sigmas) || !edgesAsUsual(r) || r.stereo_rejected || stereo_drifts_) return;
    const double w = options_.usual_edge_ratio_weight;
    const auto mean = [w](double usual, double x) { return std::isnan(usual) ? x : (1 - w) * usual + w * x; };
    usual_edge_ratio_ = mean(usual_edge_ratio_, r.edge_inlier_ratio);
    usual_stereo_sigmas_ = mean(usual_stereo_sigmas_, r.stereo_map_sigmas);
}

bool TrackMonitor::checkDue(size_t n) const
{
    // A held stereo is the one the check would weigh: no check, unless the hold is yet to be judged or has lasted
    // stereo_hold_max_s.
    if (health_ == TrackHealth::Lost) return false;
    if (stereo_held_until_ && !hold_overlong_) return !hold_judged_;
    return n % size_t(options_.check_every) == 0 || failed_checks_ > 0 || unverified_after_;
}

double TrackMonitor::checkAlignsBelow() const { return stereo_drifts_ ? 1.0 : options_.lost_explained_ratio; }

bool TrackMonitor::judgeHeldStereo(const FrameReport& r, const CheckResult& c)
{
    hold_judged_ = true;
    const double fit = c.refined ? std::max(c.explained, c.refined_explained) : c.explained;
    if (fit < options_.stereo_hold_fit_below) return false;
    // A desynchronized or miscalibrated stereo is bent out of the map's shape and fits it nowhere; this one fits.
    out_ << "stereo check at t " << std::fixed << std::setprecision(3) << r.t << ": the rejected stereo fits the map ("
         << std::setprecision(3) << fit << " explained): the pose is what disagrees; the stereo is released"
         << std::endl;
    releaseStereo();
    stereo_vouched_until_ = r.t + options_.stereo_check_hold_s;
    return true;
}

CheckOutcome TrackMonitor::checked(const FrameReport& r, const CheckResult& c)
{
    if (stereo_held_until_ && !hold_judged_ && !judgeHeldStereo(r, c)) return CheckOutcome::StereoHeld;
    const bool failed = c.refined && (c.refined_explained - c.explained >= options_.lost_min_gain ||
                                      c.explained < options_.lost_explained_floor);
    failed_checks_ = failed ? failed_checks_ + 1 : 0;
    if (failed)
    {
        flagUnverified(last_verified_t_);  // since the last confirmed pose
        return CheckOutcome::Failed;
    }
    // After a restart at a fix, the stereo that passes the check is the stereo the fix came from: the pose is
    // confirmed only when the edges (the left image alone) fit as usual too.
    if (health_ == TrackHealth::Restarted && !edgesAsUsual(r)) return CheckOutcome::PassedUnconfirmed;
    stereo_drifts_ = false;
    if (hold_overlong_)
    {
        // The stereo the gate held explains the map at the tracked pose: it was the edge pose that disagreed.
        out_ << "stereo check at t " << std::fixed << std::setprecision(3) << r.t
             << ": a check confirmed the pose; the held stereo is released" << std::endl;
        releaseStereo();
    }
    health_ = TrackHealth::Verified;
    closeUnverified(r.t);
    last_verified_t_ = r.t;
    return CheckOutcome::Passed;
}

bool TrackMonitor::lostByMisses(const FrameReport& r) const { return r.alignment_misses >= options_.lost_after_misses; }

bool TrackMonitor::lossDue(const FrameReport& r) const
{
    const bool unconfirmed_restart = health_ == TrackHealth::Restarted && options_.lost_unconfirmed_restart_s > 0 &&
                                     r.t - restarted_at_t_ > options_.lost_unconfirmed_restart_s;
    return health_ != TrackHealth::Lost &&
           (lostByMisses(r) || failed_checks_ >= options_.lost_after_failed_checks || unconfirmed_restart);
}

void TrackMonitor::searchBegun()
{
    failed_checks_ = 0;
    flagUnverified(last_verified_t_);
    before_loss_ = health_;
    health_ = TrackHealth::Lost;
}

void TrackMonitor::fixFound(double t_fix, bool agrees_with_track)
{
    flagUnverified(last_verified_t_);
    closeUnverified(t_fix);
    last_verified_t_ = t_fix;
    if (agrees_with_track)
    {
        health_ = before_loss_ == TrackHealth::Doubted ? TrackHealth::Verified : before_loss_;
        if (health_ == TrackHealth::Restarted) restarted_at_t_ = t_fix;  // a second fix agrees: time to confirm anew
        return;
    }
    // A restart rests on one fix of the stereo geometry (wrong when the stereo is, e.g. desynchronized): the track
    // from it is unverified until a check confirms it.
    health_ = TrackHealth::Restarted;
    restarted_at_t_ = t_fix;
    flagUnverified(t_fix);
}

void TrackMonitor::ended()
{
    if (health_ == TrackHealth::Lost) flagUnverified(last_verified_t_);
    closeUnverified(INFINITY);  // a stretch no check confirmed runs to the end
}

}  // namespace quasiloc::tracking
