#pragma once
// A tracking session: the product's run around the tracker, frame by frame from a FrameSource. Each frame flows
// one way:
//     read (InputGuard) -> tracker step (Tracker::step, gated by the monitor's StereoGate) -> loss check
//     (GlobalStarter::checkTrack, when the monitor says it is due) -> TrackMonitor (the track's health) ->
//     relocalization (BackgroundSearch, when the monitor declares a loss) -> RunLog (written, never read back)
//   start         from the ground truth of the first frames, or by global localization by geometry
//                 ([Initialization] init; GlobalStarter), after a static initialization when the platform stands;
//   policy        the track's health, the stereo gate, when to check, when the track is lost and which frames are
//                 unverified: TrackMonitor (track_monitor.h, [TrackMonitor]);
//   relocalize    global localization on its own thread while the tracker goes on; a fix that agrees with the
//                 track (PoseHistory) withdraws the loss, otherwise the tracker restarts at the fix and the frames
//                 since are tracked again;
//   bad input     frames whose timestamp does not increase, or with no IMU sample since the previous frame, are
//                 rejected with a warning and not tracked (InputGuard, input_guard.h); the run goes on.
// quasiloc-track is options -> session -> outputs; the unit tests drive the session without the program.
#include <mrpt/system/CTimeLogger.h>

#include <deque>
#include <memory>
#include <optional>
#include <ostream>
#include <quasiloc/dataset/calibration.h>
#include <functional>
#include <quasiloc/dataset/frame_source.h>
#include <quasiloc/estimation/estimator_options.h>
#include <quasiloc/estimation/map_refinement.h>
#include <quasiloc/estimation/reweighting.h>
#include <quasiloc/frontend/frontend.h>
#include <quasiloc/reloc/geometric_localizer.h>
#include <quasiloc/tracking/background_search.h>
#include <quasiloc/tracking/global_start.h>
#include <quasiloc/tracking/input_guard.h>
#include <quasiloc/tracking/map_context.h>
#include <quasiloc/tracking/pose_history.h>
#include <quasiloc/tracking/run_log.h>
#include <quasiloc/tracking/track_monitor.h>
#include <quasiloc/tracking/tracker.h>
#include <quasiloc/tracking/tracking_options.h>

namespace quasiloc::tracking
{
/** The tracker's IMU model from the calibration's [imu] (dataset/calibration.h). */
estimation::ImuNoise imuNoise(const dataset::ImuCalibration& c);

/** Every option of a session, one INI section each (quasi-image options belong to the MapContext). */

struct SessionOptions
{
    /** The tracker's defaults where a shared section's struct serves other programs differently: one window round
     *  (no structural factor by default), uniform reweighting of the structural factors, 4 ORB levels for the stereo
     *  points, and the render's completion radius 1 (docs/experiments.md has the measurements). */
    SessionOptions();

    TrackingRunOptions tracker;                        ///< [Tracking] + [Initialization] + [MapFactors]
    TrackMonitorOptions monitor;                       ///< [TrackMonitor]
    RelocalizationOptions relocalization;              ///< [Relocalization]
    reloc::GeometricLocalizationOptions localization;  ///< [GeometricLocalization]
    estimation::MapRefinementOptions refinement;       ///< [MapRefinement] + [DirectAlignment]
    estimation::EstimatorOptions estimator;            ///< [Estimator]
    estimation::ReweightingOptions reweighting;        ///< [Reweighting]
    frontend::FrontendOptions frontend;                ///< [Features] [PointMatching] [Lines] [Stereo]
    quasi::QuasiOptions quasi;                         ///< [QuasiImage] (the MapContext's renderers)

    /** Loads and checks every section (unknown keys are errors naming `config_name`). */
    void load(const mrpt::config::CConfigFileBase& cfg, const std::string& config_name);
    /** The sections for core::writeEffectiveConfig. */
    std::vector<core::OptionsSection> sections() const;
};

class TrackingSession
{
   public:
    /** `context`, `source` and `console` must outlive the session. InputError for bad options or calibration. */
    TrackingSession(const SessionOptions& options, MapContext& context, dataset::FrameSource& source,
                    const dataset::ImuCalibration& imu, std::ostream& console);
    ~TrackingSession();

    /** Starts and tracks to the end of the frames (or max_frames). InputError naming `input` when no start is found
     *  or the frames end right after it. */
    SessionSummary run(const std::string& input);

    const RunLog& log() const { return log_; }
    /** initialization.txt: every attempt of global localization (empty without a starter). */
    std::string initializationRecord() const { return starter_ ? starter_->record() : std::string(); }
    bool hasStarter() const { return bool(starter_); }
    const Tracker& tracker() const { return *tracker_; }
    /** Per-stage wall time over the run (one timer, mrpt's CTimeLogger): what --print-timing prints. */
    std::string timing() const;

    /** Called after each tracked frame, before a loss is acted on: a test harness's hook (test_harness.h). */
    using FrameHook = std::function<void(const FrameReport&, TrackingSession&)>;
    void setFrameHook(FrameHook hook) { frame_hook_ = std::move(hook); }
    /** Restarts the tracker at T_world_cam0 at time t (the latest tracked frame's) with the track's velocity and
     *  biases and the confidence of a given start, as a tracker that jumped there on its own would be. */
    void restartTrackerAt(double t, const Eigen::Isometry3d& T_world_cam0);
    /** The time of the start frame. */
    double startTime() const { return t_start_; }

   private:
    /** A loss is checked for and relocalized from (relocalize, and map updates on). */
    bool relocalizes() const;
    /** The source's next frame (its time is the first frame's if none was read yet). */
    bool readSource(dataset::StereoFrame& out);
    bool nextFrame(dataset::StereoFrame& out);
    void startFromGroundTruth(const std::string& input);
    void startGlobally(const std::string& input);
    void trackFrame(dataset::StereoFrame& f);
    /** The geometry check of the tracked pose, when the monitor says it is due; returns its explained share (NaN
     *  when not checked). */
    double checkTrack(const dataset::StereoFrame& f, const TrackStep& step, size_t number, double& ms);
    /** A loss begins a relocalization search; a search under way gets the frame. True when it restarted the track. */
    bool relocalize(const dataset::StereoFrame& f, const FrameReport& r, double& ms);
    /** A fix: the loss is withdrawn when it agrees with the track, else the tracker restarts there. */
    bool settle(const GlobalInitialState& found, double t_now);
    void finishSearch(dataset::StereoFrame& f, bool& have_frame);
    void recordTiming(const FrameReport& r, double ms_check, double ms_search);

    SessionOptions options_;
    MapContext& context_;
    dataset::FrameSource& source_;
    dataset::ImuCalibration imu_;
    std::ostream& out_;
    InputGuard guard_;
    Eigen::Isometry3d T_body_cam_;
    std::unique_ptr<frontend::Frontend> frontend_;      ///< the global starter's
    std::unique_ptr<reloc::StereoCloud> stereo_cloud_;  ///< stereo_map_points = dense
    std::unique_ptr<Tracker> tracker_;
    std::unique_ptr<GlobalStarter> starter_;
    std::optional<BackgroundSearch> search_;
    RunLog log_;
    TrackMonitor monitor_;
    PoseHistory history_;
    TrackEstimate latest_;  ///< the tracker's latest estimate (what a restart takes its biases from)
    mutable mrpt::system::CTimeLogger timer_{true, "quasiloc-track"};
    SessionSummary summary_;
    /** Frames to track before reading more: the start's, or, after a restart, those after the fix. */
    std::deque<dataset::StereoFrame> queued_;
    /** Keeps f's IMU samples (once, in time order) and forgets those before the last verified frame. */
    void keepImuSinceVerified(const dataset::StereoFrame& f);
    /** The orientation of the last verified frame and the samples since, for a search after a loss at t_loss. */
    std::optional<HeadingPrior> headingPrior(double t_loss) const;
    /** Where the lost track puts frame r, for the search ([Relocalization] relocalize_odometry_drift_ratio). */
    std::optional<OdometryPrediction> odometryPrediction(const FrameReport& r);
    /** The lost track went faster than the platform can ([Initialization] init_max_speed_m_s): no prediction for
     *  the rest of the loss. */
    bool odometry_diverged_ = false;
    /** Frames tracked since the search began, with the track's state at each (a restart tracks the later ones
     *  again, from the biases the track had at the fix). */
    std::deque<std::pair<dataset::StereoFrame, estimation::FrameState>> since_loss_;
    /** The IMU samples since the last verified frame: they carry its orientation to a loss (HeadingPrior). */
    std::deque<dataset::ImuSample> imu_since_verified_;
    ImuBiasPrior start_biases_;
    double t_start_ = 0;
    FrameHook frame_hook_;
};

}  // namespace quasiloc::tracking
