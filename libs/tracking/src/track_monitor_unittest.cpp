// The track monitor from tables of events, without images: each row is one event and what the policy must say
// after it (health, the next frame's stereo bound, whether a check is due, whether a loss is due), and each table
// ends with the unverified stretches handed to the log.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <quasiloc/tracking/track_monitor.h>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace quasiloc::tracking
{
namespace
{
using H = TrackHealth;

/** The monitor under test, with the frame counter and the log's stretches. */
struct Harness
{
    TrackMonitorOptions options;
    std::ostringstream console;
    std::vector<std::pair<double, double>> stretches;
    TrackMonitor monitor;
    FrameReport last;
    size_t n = 0;  ///< frames tracked since the start (the session's counter)
    std::vector<CheckOutcome> outcomes;

    explicit Harness(const TrackMonitorOptions& o)
        : options(o), monitor(o, console, [this](double a, double b) { stretches.emplace_back(a, b); })
    {}
};

using Event = std::function<void(Harness&)>;

/** A tracked frame: a keyframe by default, its alignment accepted, its stereo measured at 1 sigma. */
struct Frame
{
    double t;
    bool map_update = true;
    double stereo_sigmas = 1.0;
    double edge_ratio = 0.5;
    int misses = 0;
};

Event start(double t)
{
    return [t](Harness& h) {
        h.monitor.started(t);
        h.n = 1;
    };
}
Event fault(double t)
{
    return [t](Harness& h) { h.monitor.inputFault(t); };
}
Event frame(Frame f)
{
    return [f](Harness& h) {
        FrameReport r;
        r.t = f.t;
        r.keyframe = true;
        r.map_update = f.map_update;
        r.edge_inlier_ratio = f.edge_ratio;
        r.alignment_misses = f.misses;
        if (f.map_update) r.stereo_map_sigmas = f.stereo_sigmas;
        // The tracker applies the gate the monitor set before the frame.
        if (f.map_update) r.stereo_rejected = h.monitor.stereoGate().rejects(f.stereo_sigmas, f.edge_ratio);
        r.lost = h.monitor.lostByMisses(r);
        ++h.n;
        h.monitor.frameTracked(r);
        h.last = r;
    };
}
/** A check of the last frame: explained share, and after aligning from the tracked pose. */
Event check(double explained, double refined_explained)
{
    return [=](Harness& h) { h.outcomes.push_back(h.monitor.checked(h.last, {explained, true, refined_explained})); };
}
Event searchBegun()
{
    return [](Harness& h) { h.monitor.searchBegun(); };
}
Event fix(double t, bool agrees)
{
    return [=](Harness& h) {
        h.monitor.fixFound(t, agrees);
        if (!agrees) h.last = FrameReport{};  // the tracker restarts: no miss counted yet
    };
}
Event ended()
{
    return [](Harness& h) { h.monitor.ended(); };
}

struct Row
{
    const char* what;
    Event event;
    H health;
    double bound;  ///< the next frame's stereo gate bound
    bool check_due;
    bool loss_due;
};

void runTable(const TrackMonitorOptions& o, const std::vector<Row>& rows,
              const std::vector<std::pair<double, double>>& stretches, const std::vector<CheckOutcome>& outcomes)
{
    Harness h(o);
    for (const Row& row : rows)
    {
        SCOPED_TRACE(row.what);
        row.event(h);
        EXPECT_EQ(toString(h.monitor.health()), std::string(toString(row.health)));
        EXPECT_DOUBLE_EQ(h.monitor.stereoGate().max_sigmas, row.bound);
        EXPECT_EQ(h.monitor.checkDue(h.n), row.check_due);
        EXPECT_EQ(h.monitor.lossDue(h.last), row.loss_due);
    }
    ASSERT_EQ(h.stretches.size(), stretches.size());
    for (size_t i = 0; i < stretches.size(); ++i)
    {
        EXPECT_NEAR(h.stretches[i].first, stretches[i].first, 1e-9) << "stretch " << i;
        EXPECT_EQ(h.stretches[i].second, stretches[i].second) << "stretch " << i;
    }
    ASSERT_EQ(h.outcomes.size(), outcomes.size());
    for (size_t i = 0; i < outcomes.size(); ++i) EXPECT_EQ(h.outcomes[i], outcomes[i]) << "check " << i;
}

TrackMonitorOptions testOptions()
{
    TrackMonitorOptions o;  // bounds 3 / 2 sigmas, hold 2 s, checks every 5 frames, two failed checks lose it
    o.lost_after_misses = 3;
    return o;
}

TEST(TrackMonitor, CleanTrackIsCheckedOnSchedule)
{
    runTable(testOptions(),
             {{"start", start(0.0), H::Verified, 3, false, false},
              {"frame 2", frame({0.1}), H::Verified, 3, false, false},
              {"frame 3", frame({0.2}), H::Verified, 3, false, false},
              {"frame 4", frame({0.3}), H::Verified, 3, false, false},
              {"frame 5: due", frame({0.4}), H::Verified, 3, true, false},
              {"passed", check(0.9, 0.9), H::Verified, 3, true, false},
              {"frame 6", frame({0.5}), H::Verified, 3, false, false},
              {"end", ended(), H::Verified, 3, false, false}},
             {}, {CheckOutcome::Passed});
}

TEST(TrackMonitor, TwoFailedChecksLoseTheTrackAndAnAgreeingFixWithdrawsTheLoss)
{
    runTable(testOptions(),
             {{"start", start(0.0), H::Verified, 3, false, false},
              {"frame 2", frame({0.1}), H::Verified, 3, false, false},
              {"frame 3", frame({0.2}), H::Verified, 3, false, false},
              {"frame 4", frame({0.3}), H::Verified, 3, false, false},
              {"frame 5: due", frame({0.4}), H::Verified, 3, true, false},
              {"passed at 0.4", check(0.9, 0.9), H::Verified, 3, true, false},
              {"frame 6", frame({0.5}), H::Verified, 3, false, false},
              {"frame 7", frame({0.6}), H::Verified, 3, false, false},
              {"frame 8", frame({0.7}), H::Verified, 3, false, false},
              {"frame 9", frame({0.8}), H::Verified, 3, false, false},
              {"frame 10: due", frame({0.9}), H::Verified, 3, true, false},
              // Aligning moves the points to explain 0.2 more: the pose is wrong. The edges stay trusted.
              {"failed once", check(0.5, 0.7), H::Doubted, 3, true, false},
              {"frame 11: due again", frame({1.0}), H::Doubted, 3, true, false},
              {"failed twice: lost", check(0.4, 0.8), H::Doubted, 3, true, true},
              {"search", searchBegun(), H::Lost, 3, false, false},
              {"frame 12 while lost", frame({1.1}), H::Lost, 3, false, false},
              {"fix at 1.1 agrees", fix(1.1, true), H::Verified, 3, false, false},
              {"frame 13", frame({1.2}), H::Verified, 3, false, false}},
             {{0.4, 1.1}}, {CheckOutcome::Passed, CheckOutcome::Failed, CheckOutcome::Failed});
}

TEST(TrackMonitor, AnInputFaultOpensTheGateUntilACheckPasses)
{
    runTable(testOptions(),
             {{"start", start(0.0), H::Verified, 3, false, false},
              {"frame 2", frame({0.1}), H::Verified, 3, false, false},
              // A gap before the frame of t = 0.5: read, not yet tracked. The stereo brings the track back.
              {"fault read", fault(0.5), H::Verified, 0, false, false},
              {"faulty frame tracked", frame({0.5}), H::EdgesSuspect, 0, true, false},
              {"frame 4", frame({0.6}), H::EdgesSuspect, 0, true, false},
              {"passed", check(0.9, 0.9), H::Verified, 3, false, false},
              {"frame 5: due", frame({0.7}), H::Verified, 3, true, false}},
             {{0.5 - 1e-6, 0.6}}, {CheckOutcome::Passed});
}

TEST(TrackMonitor, MissedAlignmentsLoseTheTrackAndARestartNeedsUsualEdges)
{
    runTable(testOptions(),
             {{"start", start(0.0), H::Verified, 3, false, false},
              {"usual edges 0.5", frame({0.1, true, 1.0, 0.5}), H::Verified, 3, false, false},
              {"miss 1", frame({0.2, false, 1.0, 0.5, 1}), H::EdgesSuspect, 0, true, false},
              {"miss 2", frame({0.3, false, 1.0, 0.5, 2}), H::EdgesSuspect, 0, true, false},
              {"miss 3: lost", frame({0.4, false, 1.0, 0.5, 3}), H::EdgesSuspect, 0, true, true},
              {"search", searchBegun(), H::Lost, 0, false, false},
              {"fix at 0.4 disagrees: restart", fix(0.4, false), H::Restarted, 0, true, false},
              // Aligned from the restart the edges fit at 0.3 < 0.8 x 0.5: the check passes but confirms nothing.
              {"poor edges", frame({0.5, true, 1.0, 0.3}), H::Restarted, 0, true, false},
              {"passed, unconfirmed", check(0.9, 0.9), H::Restarted, 0, true, false},
              {"usual edges", frame({0.6, true, 1.0, 0.5}), H::Restarted, 0, true, false},
              {"passed, confirmed", check(0.9, 0.9), H::Verified, 3, false, false}},
             {{0.0, 0.4}, {0.4, 0.6}}, {CheckOutcome::PassedUnconfirmed, CheckOutcome::Passed});
}

TEST(TrackMonitor, ARejectedStereoIsHeldThenReleased)
{
    runTable(testOptions(),
             {{"start", start(0.0), H::Verified, 3, false, false},
              {"stereo agrees", frame({0.1, true, 1.0}), H::Verified, 3, false, false},
              // 5 sigmas against the bound 3: the stereo is left out and held for 2 s at the release bound.
              {"stereo rejected", frame({0.2, true, 5.0}), H::Doubted, 2, false, false},
              {"2.5 sigmas, above the release bound", frame({1.0, true, 2.5}), H::Doubted, 2, false, false},
              {"agrees within the hold", frame({2.0, true, 1.0}), H::Doubted, 2, false, false},
              {"hold over: released, unverified", frame({3.1, true, 1.0}), H::Doubted, 3, true, false},
              {"passed", check(0.9, 0.9), H::Verified, 3, false, false}},
             {{0.2 - 1e-6, 3.1}}, {CheckOutcome::Passed});
}

TEST(TrackMonitor, AFaultDuringALossIsRememberedByAWithdrawnLoss)
{
    runTable(testOptions(),
             {{"start", start(0.0), H::Verified, 3, false, false},
              {"frame 2", frame({0.1}), H::Verified, 3, false, false},
              {"frame 3", frame({0.2}), H::Verified, 3, false, false},
              {"frame 4", frame({0.3}), H::Verified, 3, false, false},
              {"frame 5: due", frame({0.4}), H::Verified, 3, true, false},
              {"failed", check(0.4, 0.8), H::Doubted, 3, true, false},
              {"frame 6", frame({0.5}), H::Doubted, 3, true, false},
              {"failed twice", check(0.4, 0.8), H::Doubted, 3, true, true},
              {"search", searchBegun(), H::Lost, 3, false, false},
              {"fault read", fault(0.7), H::Lost, 0, false, false},
              {"faulty frame while lost", frame({0.7}), H::Lost, 0, false, false},
              // The loss is withdrawn, but the edge pose stays suspect (the fault) until a check passes.
              {"fix agrees", fix(0.7, true), H::EdgesSuspect, 0, false, false},
              {"frame 8", frame({0.8}), H::EdgesSuspect, 0, false, false},
              {"end", ended(), H::EdgesSuspect, 0, false, false}},
             {{0.0, 0.7}}, {CheckOutcome::Failed, CheckOutcome::Failed});
}

TEST(TrackMonitor, FramesThatEndDuringASearchAreUnverifiedToTheEnd)
{
    runTable(testOptions(),
             {{"start", start(0.0), H::Verified, 3, false, false},
              {"miss 1", frame({0.1, false, 1.0, 0.5, 1}), H::EdgesSuspect, 0, true, false},
              {"miss 2", frame({0.2, false, 1.0, 0.5, 2}), H::EdgesSuspect, 0, true, false},
              {"miss 3", frame({0.3, false, 1.0, 0.5, 3}), H::EdgesSuspect, 0, true, true},
              {"search", searchBegun(), H::Lost, 0, false, false},
              {"end", ended(), H::Lost, 0, false, false}},
             {{0.0, INFINITY}}, {});
}

TEST(TrackMonitor, TheUsualEdgeFitIsARunningMeanOverAgreeingFrames)
{
    Harness h(testOptions());
    h.monitor.started(0);
    EXPECT_TRUE(std::isnan(h.monitor.stereoGate().usual_edge_ratio));
    frame({0.1, true, 1.0, 0.6})(h);
    EXPECT_DOUBLE_EQ(h.monitor.stereoGate().usual_edge_ratio, 0.6);
    frame({0.2, true, 1.0, 0.45})(h);  // below 0.8 x 0.6: not as usual, kept out
    EXPECT_DOUBLE_EQ(h.monitor.stereoGate().usual_edge_ratio, 0.6);
    frame({0.25, true, 1.0, 0.5})(h);
    EXPECT_DOUBLE_EQ(h.monitor.stereoGate().usual_edge_ratio, 0.95 * 0.6 + 0.05 * 0.5);
    const double usual = h.monitor.stereoGate().usual_edge_ratio;
    frame({0.3, true, 9.0, 0.6})(h);  // rejected: the mean keeps out a frame whose stereo disagreed
    EXPECT_DOUBLE_EQ(h.monitor.stereoGate().usual_edge_ratio, usual);
    frame({0.4, false, 1.0, 0.9})(h);  // no alignment: nothing measured
    EXPECT_DOUBLE_EQ(h.monitor.stereoGate().usual_edge_ratio, usual);
}

TEST(TrackMonitor, AStereoDriftingFromTheMapIsCheckedByAligningUntilACheckPasses)
{
    // Usual stereo at 1 sigma; at 2.5 (above stereo_drift_ratio 2 x usual, below the gate's 3) the pose may be
    // drifting where the explained share stays high: unverified, and every check aligns until one passes.
    TrackMonitorOptions o = testOptions();
    o.stereo_drift_ratio = 2;
    Harness h(o);
    const double align_below = h.options.lost_explained_ratio;
    start(0)(h);
    frame({0.1, true, 1.0})(h);
    EXPECT_EQ(h.monitor.health(), H::Verified);
    EXPECT_DOUBLE_EQ(h.monitor.checkAlignsBelow(), align_below);
    frame({0.2, true, 2.5})(h);
    EXPECT_EQ(h.monitor.health(), H::Doubted);
    EXPECT_TRUE(h.monitor.checkDue(h.n));
    EXPECT_DOUBLE_EQ(h.monitor.checkAlignsBelow(), 1.0);
    EXPECT_DOUBLE_EQ(h.monitor.stereoGate().max_sigmas, 3);  // the stereo stays in: it is what pulls the pose back
    check(0.95, 0.97)(h);                                    // aligning gains little: the pose holds
    EXPECT_EQ(h.monitor.health(), H::Verified);
    EXPECT_DOUBLE_EQ(h.monitor.checkAlignsBelow(), align_below);
    frame({0.3, true, 2.5})(h);  // the drifting frame did not raise the usual distance
    EXPECT_EQ(h.monitor.health(), H::Doubted);
    check(0.80, 0.95)(h);
    frame({0.4, true, 2.6})(h);
    check(0.80, 0.96)(h);
    EXPECT_TRUE(h.monitor.lossDue(h.last));
    ended()(h);
    ASSERT_EQ(h.stretches.size(), 2u);
    EXPECT_NEAR(h.stretches[0].first, 0.2, 1e-5);
    EXPECT_EQ(h.stretches[0].second, 0.2);
    EXPECT_EQ(h.stretches[1].first, 0.2);  // from the last confirmed pose
    EXPECT_EQ(h.outcomes,
              (std::vector<CheckOutcome>{CheckOutcome::Passed, CheckOutcome::Failed, CheckOutcome::Failed}));
}

TEST(TrackMonitor, ARestartNoCheckConfirmsIsLostAgain)
{
    // Restarted at a fix whose frames' edges keep fitting worse than usual: the checks pass unconfirmed, and after
    // lost_unconfirmed_restart_s (3 s) the restart is a loss; a fix that agrees gives it another 3 s.
    TrackMonitorOptions o = testOptions();
    o.lost_unconfirmed_restart_s = 3;
    runTable(o,
             {
                 {"start", start(0), H::Verified, 3, false, false},
                 {"usual edges 0.5", frame({0.1, true, 1.0, 0.5}), H::Verified, 3, false, false},
                 {"miss 1", frame({0.2, false, 1.0, 0.5, 1}), H::EdgesSuspect, 0, true, false},
                 {"miss 2", frame({0.3, false, 1.0, 0.5, 2}), H::EdgesSuspect, 0, true, false},
                 {"miss 3: lost", frame({0.4, false, 1.0, 0.5, 3}), H::EdgesSuspect, 0, true, true},
                 {"search", searchBegun(), H::Lost, 0, false, false},
                 {"restart at 0.5", fix(0.5, false), H::Restarted, 0, true, false},
                 {"poor edges at 1.0", frame({1.0, true, 1.0, 0.3}), H::Restarted, 0, true, false},
                 {"passes unconfirmed", check(0.9, 0.9), H::Restarted, 0, true, false},
                 {"poor edges at 3.5", frame({3.5, true, 1.0, 0.3}), H::Restarted, 0, true, false},
                 {"poor edges at 3.6: unconfirmed 3.1 s", frame({3.6, true, 1.0, 0.3}), H::Restarted, 0, true, true},
                 {"search", searchBegun(), H::Lost, 0, false, false},
                 {"a fix at 3.7 agrees", fix(3.7, true), H::Restarted, 0, false, false},
                 {"poor edges at 6.6", frame({6.6, true, 1.0, 0.3}), H::Restarted, 0, false, false},
                 {"poor edges at 6.8", frame({6.8, true, 1.0, 0.3}), H::Restarted, 0, true, true},
             },
             {{0.0, 0.5}, {0.5, 3.7}}, {CheckOutcome::PassedUnconfirmed});
}

TEST(TrackMonitor, ALostTrackIsTrackedByOdometryWithTheStereoUngated)
{
    TrackMonitorOptions o = testOptions();
    o.odometry_while_lost = true;
    Harness h(o);
    start(0)(h);
    frame({0.1})(h);
    EXPECT_TRUE(h.monitor.stereoGate().map_terms);
    EXPECT_DOUBLE_EQ(h.monitor.stereoGate().max_sigmas, 3);
    searchBegun()(h);
    EXPECT_FALSE(h.monitor.stereoGate().map_terms);
    EXPECT_DOUBLE_EQ(h.monitor.stereoGate().max_sigmas, 0);
    fix(0.3, true)(h);  // withdrawn: the map terms and the gate return
    EXPECT_TRUE(h.monitor.stereoGate().map_terms);
    EXPECT_DOUBLE_EQ(h.monitor.stereoGate().max_sigmas, 3);
}

TEST(TrackMonitor, AHoldThatLastsIsCheckedOnEveryFrameAndFailedChecksLoseTheTrack)
{
    // Every rejected frame renews the hold; after stereo_hold_max_s (3 s) of it the checks are due again.
    TrackMonitorOptions o = testOptions();
    o.stereo_hold_max_s = 3;
    runTable(o,
             {{"start", start(0.0), H::Verified, 3, false, false},
              {"stereo rejected", frame({0.2, true, 5.0}), H::Doubted, 2, false, false},
              {"rejected at 1.2: renewed", frame({1.2, true, 2.5}), H::Doubted, 2, false, false},
              {"rejected at 2.2: renewed", frame({2.2, true, 2.5}), H::Doubted, 2, false, false},
              {"held 3 s: checks due", frame({3.2, true, 2.5}), H::Doubted, 2, true, false},
              {"failed once", check(0.5, 0.7), H::Doubted, 2, true, false},
              {"still held", frame({3.3, true, 2.5}), H::Doubted, 2, true, false},
              {"failed twice: lost", check(0.4, 0.8), H::Doubted, 2, true, true},
              {"search", searchBegun(), H::Lost, 2, false, false},
              {"end", ended(), H::Lost, 2, false, false}},
             {{0.0, INFINITY}}, {CheckOutcome::Failed, CheckOutcome::Failed});
}

TEST(TrackMonitor, WithoutABoundAHoldRenewedByRejectionsIsNeverChecked)
{
    Harness h(testOptions());
    start(0.0)(h);
    for (double t = 0.2; t < 10; t += 0.5)
    {
        frame({t, true, 5.0})(h);
        EXPECT_FALSE(h.monitor.checkDue(h.n)) << "t " << t;
    }
    EXPECT_EQ(h.monitor.health(), H::Doubted);
}

TEST(TrackMonitor, ACheckThatConfirmsAPoseAfterALongHoldReleasesTheStereo)
{
    TrackMonitorOptions o = testOptions();
    o.stereo_hold_max_s = 3;
    runTable(o,
             {{"start", start(0.0), H::Verified, 3, false, false},
              {"stereo agrees", frame({0.1, true, 1.0}), H::Verified, 3, false, false},
              {"stereo rejected", frame({0.2, true, 5.0}), H::Doubted, 2, false, false},
              {"rejected at 1.2", frame({1.2, true, 2.5}), H::Doubted, 2, false, false},
              {"rejected at 2.2", frame({2.2, true, 2.5}), H::Doubted, 2, false, false},
              {"held 3 s: checks due", frame({3.2, true, 2.5}), H::Doubted, 2, true, false},
              {"passed: released", check(0.9, 0.9), H::Verified, 3, false, false},
              {"2.5 sigmas pass the bound of 3", frame({3.3, true, 2.5}), H::Verified, 3, false, false}},
             {{0.2 - 1e-6, 3.2}}, {CheckOutcome::Passed});
}

TEST(TrackMonitor, ARejectedStereoThatFitsTheMapIsReleasedAndTheCheckJudgesThePose)
{
    // The check after a failed one: the gate rejects the stereo at the (wrong) edge pose, but aligned it fits the
    // map, so the disagreement is the pose's. The stereo stays in, ungated, and the second failed check loses the
    // track at once instead of a hold that no check would end.
    TrackMonitorOptions o = testOptions();
    o.stereo_hold_fit_below = 0.7;
    runTable(o,
             {{"start", start(0.0), H::Verified, 3, false, false},
              {"stereo agrees", frame({0.1, true, 1.0}), H::Verified, 3, false, false},
              {"stereo rejected: a check is due", frame({0.2, true, 5.0}), H::Doubted, 2, true, false},
              {"fits when aligned: released, failed", check(0.5, 0.92), H::Doubted, 0, true, false},
              {"ungated", frame({0.3, true, 5.0}), H::Doubted, 0, true, false},
              {"failed twice: lost", check(0.5, 0.9), H::Doubted, 0, true, true},
              {"search", searchBegun(), H::Lost, 0, false, false},
              {"end", ended(), H::Lost, 0, false, false}},
             {{0.0, INFINITY}}, {CheckOutcome::Failed, CheckOutcome::Failed});
}

TEST(TrackMonitor, ARejectedStereoThatFitsNowhereStaysHeld)
{
    // A desynchronized stereo: aligned from the tracked pose it still explains little of the map, so it is held
    // and the check does not judge the pose with it.
    TrackMonitorOptions o = testOptions();
    o.stereo_hold_fit_below = 0.7;
    runTable(o,
             {{"start", start(0.0), H::Verified, 3, false, false},
              {"stereo agrees", frame({0.1, true, 1.0}), H::Verified, 3, false, false},
              {"stereo rejected: a check is due", frame({0.2, true, 5.0}), H::Doubted, 2, true, false},
              {"fits nowhere: held", check(0.3, 0.4), H::Doubted, 2, false, false},
              {"rejected at 1.2: renewed", frame({1.2, true, 2.5}), H::Doubted, 2, false, false},
              {"agrees for 2 s: released", frame({3.3, true, 1.0}), H::Doubted, 3, true, false},
              {"passed (frame 5: on schedule)", check(0.9, 0.9), H::Verified, 3, true, false}},
             {{0.2 - 1e-6, 3.3}}, {CheckOutcome::StereoHeld, CheckOutcome::Passed});
}

TEST(TrackMonitor, ALostTrackAsksForAWiderVelocity)
{
    TrackMonitorOptions o = testOptions();
    o.lost_velocity_random_walk = 0.5;
    Harness h(o);
    start(0)(h);
    frame({0.1})(h);
    EXPECT_DOUBLE_EQ(h.monitor.stereoGate().velocity_random_walk, 0);
    searchBegun()(h);
    EXPECT_DOUBLE_EQ(h.monitor.stereoGate().velocity_random_walk, 0.5);
    fix(0.3, false)(h);  // restarted: no longer lost
    EXPECT_DOUBLE_EQ(h.monitor.stereoGate().velocity_random_walk, 0);
}

TEST(TrackMonitor, RejectsInconsistentOptions)
{
    TrackMonitorOptions o;
    o.lost_explained_floor = 0.9;
    o.lost_explained_ratio = 0.7;
    std::ostringstream out;
    EXPECT_ANY_THROW(TrackMonitor(o, out, [](double, double) {}));
}
}  // namespace
}  // namespace quasiloc::tracking
