#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/tracking/tracking_session.h>

#include <chrono>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace quasiloc::tracking
{
estimation::ImuNoise imuNoise(const dataset::ImuCalibration& c)
{
    estimation::ImuNoise n;
    n.gyro_noise_density = c.gyroscope_noise_density;
    n.acc_noise_density = c.accelerometer_noise_density;
    n.gyro_random_walk = c.gyroscope_random_walk;
    n.acc_random_walk = c.accelerometer_random_walk;
    n.gravity_m_s2 = c.gravity_m_s2;
    return n;
}

namespace
{

ImuBiasPrior calibrationBiasPrior(const dataset::ImuCalibration& c)
{
    ImuBiasPrior p;
    p.gyro_bias = c.gyroscope_bias;
    p.acc_bias = c.accelerometer_bias;
    p.gyro_sigma = c.gyroscope_bias_sigma;
    p.acc_sigma = c.accelerometer_bias_sigma;
    p.source = "calibration";
    return p;
}

std::string describe(const ImuBiasPrior& p)
{
    std::ostringstream s;
    s.precision(4);
    s << "gyroscope bias [" << p.gyro_bias.transpose() << "] +- " << p.gyro_sigma << " rad/s, accelerometer bias ["
      << p.acc_bias.transpose() << "] +- " << p.acc_sigma << " m/s^2 (" << p.source << ")";
    return s.str();
}

double msSince(std::chrono::steady_clock::time_point t0)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

const char* mapTermName(MapTerm t) { return t == MapTerm::Factor ? "factor" : t == MapTerm::None ? "none" : "auto"; }
}  // namespace

SessionOptions::SessionOptions()
{
    estimator.outer_iterations = 1;
    reweighting.mode = estimation::ReweightingMode::Uniform;
    frontend.features.orb_levels = 4;
    quasi.completion_radius_px = 1;
}

void SessionOptions::load(const mrpt::config::CConfigFileBase& cfg, const std::string& name)
{
    core::loadOptionsChecked(tracker, cfg, "Tracking", name);
    core::loadOptionsChecked(tracker.initialization, cfg, "Initialization", name);
    core::loadOptionsChecked(tracker.factors, cfg, "MapFactors", name);
    tracker.factors.check(name);
    core::loadOptionsChecked(monitor, cfg, "TrackMonitor", name);
    monitor.check(name);
    core::loadOptionsChecked(relocalization, cfg, "Relocalization", name);
    // The prediction is the lost track: without odometry_while_lost the map terms pull it to a wrong place.
    core::require(relocalization.relocalize_odometry_drift_ratio <= 0 || monitor.odometry_while_lost,
                  name + ": [Relocalization] relocalize_odometry_drift_ratio",
                  "needs [TrackMonitor] odometry_while_lost = true (the prediction is the track while lost)");
    core::loadOptionsChecked(localization, cfg, "GeometricLocalization", name);
    localization.check(name);
    core::loadOptionsChecked(refinement.direct, cfg, "DirectAlignment", name);
    core::loadOptionsChecked(refinement, cfg, "MapRefinement", name);
    refinement.check(name);
    core::loadOptionsChecked(estimator, cfg, "Estimator", name);
    estimator.check(name);
    core::loadOptionsChecked(reweighting, cfg, "Reweighting", name);
    reweighting.check(name);
    // The front-end sections the tracker uses ([LineMatching] and [Association] serve the database programs).
    core::loadOptionsChecked(frontend.features, cfg, "Features", name);
    core::loadOptionsChecked(frontend.point_matching, cfg, "PointMatching", name);
    core::loadOptionsChecked(frontend.lines, cfg, "Lines", name);
    core::loadOptionsChecked(frontend.stereo, cfg, "Stereo", name);
    frontend.check(name);
    core::loadOptionsChecked(quasi, cfg, "QuasiImage", name);
    quasi.check(name);
}

std::vector<core::OptionsSection> SessionOptions::sections() const
{
    return {{"Tracking", &tracker},
            {"Initialization", &tracker.initialization},
            {"MapFactors", &tracker.factors},
            {"TrackMonitor", &monitor},
            {"Relocalization", &relocalization},
            {"GeometricLocalization", &localization},
            {"MapRefinement", &refinement},
            {"DirectAlignment", &refinement.direct},
            {"Estimator", &estimator},
            {"Reweighting", &reweighting},
            {"Features", &frontend.features},
            {"PointMatching", &frontend.point_matching},
            {"Lines", &frontend.lines},
            {"Stereo", &frontend.stereo},
            {"QuasiImage", &quasi}};
}

TrackingSession::TrackingSession(const SessionOptions& options, MapContext& context, dataset::FrameSource& source,
                                 const dataset::ImuCalibration& imu, std::ostream& console)
    : options_(options),
      context_(context),
      source_(source),
      imu_(imu),
      out_(console),
      guard_(console),
      T_body_cam_(core::toIsometry(source.rig().T_body_left)),
      frontend_(std::make_unique<frontend::Frontend>(options.frontend)),
      monitor_(options.monitor, console,
               [this](double after_t, double up_to_t) { log_.markUnverified(after_t, up_to_t); })
{
    const TrackerOptions& o = options_.tracker;
    estimation::ImuNoise noise = imuNoise(imu_);
    noise.gap_s = options_.estimator.imu_gap_s;
    noise.gap_max_s = options_.estimator.imu_gap_max_s;
    noise.gap_acc_sigma = options_.estimator.imu_gap_acc_sigma;
    noise.gap_gyro_sigma = options_.estimator.imu_gap_gyro_sigma;
    tracker_ = std::make_unique<Tracker>(o, options_.refinement, options_.estimator, options_.reweighting, source.rig(),
                                         noise, context.renderer(), options_.frontend);
    // auto resolves by the map (Tracker's constructor): factor on a thin map with reflectivity, else none.
    out_ << "map term: " << mapTermName(tracker_->mapTerm())
         << (tracker_->mapTermReason().empty() ? "" : " (" + tracker_->mapTermReason() + ")") << std::endl;
    if (o.initialization.init == InitMode::Global || relocalizes())
    {
        starter_ = std::make_unique<GlobalStarter>(context, source.rig(), o.initialization, options_.localization,
                                                   options_.refinement, *frontend_, noise, out_);
        starter_->setBiasPrior(calibrationBiasPrior(imu_));
    }
    if (o.factors.stereo_map_factor && o.map_updates)
    {
        tracker_->setMapDistanceField(context.distanceField(options_.localization).get());
        if (o.factors.stereo_map_points == StereoMapPoints::Dense)
        {
            stereo_cloud_ = std::make_unique<reloc::StereoCloud>(source.rig(), options_.localization.stereo);
            tracker_->setStereoCloud(stereo_cloud_.get());
        }
    }
}

TrackingSession::~TrackingSession() { timer_.clear(true); }  // CTimeLogger dumps what it holds at destruction

std::string TrackingSession::timing() const { return timer_.getStatsAsText(); }

void TrackingSession::recordTiming(const FrameReport& r, double ms_check, double ms_search)
{
    const std::pair<const char*, double> stages[] = {
        {"frame.predict", r.ms_predict}, {"frame.edge_field", r.ms_image},    {"frame.align", r.ms_align},
        {"frame.visual", r.ms_visual},   {"frame.window", r.ms_window},       {"frame.tracker_total", r.ms_total},
        {"frame.check", ms_check},       {"frame.search_handover", ms_search}};
    for (const auto& [name, ms] : stages)
        if (ms > 0) timer_.registerUserMeasure(name, ms * 1e-3, true);
}

bool TrackingSession::relocalizes() const
{
    // Relocalization is a use of the map: the no-map baselines (map_updates = false) stay pure.
    return options_.relocalization.relocalize && options_.tracker.map_updates;
}

bool TrackingSession::readSource(dataset::StereoFrame& out)
{
    // Frames the guard rejects (timestamp not increasing, no IMU) are skipped: reported, never a stop.
    do
    {
        if (!source_.next(out)) return false;
        if (!summary_.t_first_frame) summary_.t_first_frame = out.timestamp;
    } while (!guard_.accept(out));
    if (guard_.lastWasFaulty(options_.monitor.input_gap_s)) monitor_.inputFault(out.timestamp);
    return true;
}

bool TrackingSession::nextFrame(dataset::StereoFrame& out)
{
    if (queued_.empty()) return readSource(out);
    out = std::move(queued_.front());
    queued_.pop_front();
    return true;
}

void TrackingSession::startFromGroundTruth(const std::string& input)
{
    // The first two frames with ground truth give the initial pose and velocity; the IMU samples up to the first
    // of them, if the platform stood still over them, its gyroscope bias.
    dataset::StereoFrame f0, f1;
    StaticInitializer still(imu_.gyroscope_noise_density);
    while (readSource(f0))
    {
        still.add(f0.imu);
        if (f0.T_world_cam0) break;
    }
    core::require(bool(f0.T_world_cam0), input, "no frame with a ground-truth pose");
    core::require(readSource(f1) && f1.T_world_cam0, input, "the second frame has no ground-truth pose");
    const Eigen::Vector3d p0 = (core::toIsometry(*f0.T_world_cam0) * T_body_cam_.inverse()).translation();
    const Eigen::Vector3d p1 = (core::toIsometry(*f1.T_world_cam0) * T_body_cam_.inverse()).translation();
    const Eigen::Isometry3d T_world_cam = core::toIsometry(*f0.T_world_cam0);
    const ImuBiasPrior biases = options_.tracker.initialization.static_initialization
                                    ? withStaticEstimate(calibrationBiasPrior(imu_), still.estimate())
                                    : calibrationBiasPrior(imu_);
    latest_ = tracker_->initialize(f0.timestamp, T_world_cam, (p1 - p0) / (f1.timestamp - f0.timestamp), biases, &f0);
    start_biases_ = biases;
    queued_.push_back(std::move(f1));
    summary_.T_world_cam0_start = T_world_cam;
    log_.addStart(f0, T_world_cam);
    history_.add(f0.timestamp, T_world_cam);
    t_start_ = f0.timestamp;
}

void TrackingSession::startGlobally(const std::string& input)
{
    // A region prior (a large map): the candidate positions within search_radius_m of search_center_m only.
    const InitializationOptions& o = options_.tracker.initialization;
    std::optional<SearchPrior> region;
    if (o.search_radius_m > 0) region = SearchPrior{o.search_center_m, 0.0, o.search_radius_m, 0.0};
    const auto t0 = std::chrono::steady_clock::now();
    auto found = starter_->find([this](dataset::StereoFrame& out) { return readSource(out); }, "init", region);
    summary_.start_search_s = msSince(t0) / 1000;
    core::require(found.has_value(), input,
                  "global initialisation found no start: no two frames localized by geometry and agreed with the "
                  "IMU (see the printed attempts)");
    GlobalInitialState& start = *found;
    latest_ = tracker_->initializeFromGlobal(start.anchor.timestamp, start.T_world_cam0, *start.v_world, start.biases,
                                             &start.anchor);  // a pair: always has a velocity
    start_biases_ = start.biases;
    for (auto& p : start.pending) queued_.push_back(std::move(p));
    summary_.T_world_cam0_start = start.T_world_cam0;
    log_.addStart(start.anchor, start.T_world_cam0);
    history_.add(start.anchor.timestamp, start.T_world_cam0);
    t_start_ = start.anchor.timestamp;
    if (start.anchor.T_world_cam0) summary_.T_world_cam0_start_truth = core::toIsometry(*start.anchor.T_world_cam0);
}

SessionSummary TrackingSession::run(const std::string& input)
{
    if (options_.tracker.initialization.init == InitMode::GroundTruth)
    {
        startFromGroundTruth(input);
        summary_.T_world_cam0_start_truth = summary_.T_world_cam0_start;
    }
    else
        startGlobally(input);
    monitor_.started(t_start_);
    // After the start: the search thread takes over the starter's console lines (the start's are printed as made).
    if (starter_ && relocalizes()) search_.emplace(*starter_, options_.relocalization.relocalize_latest_only);
    dataset::StereoFrame f;
    core::require(nextFrame(f), input, "no frame after the initial one");
    out_ << "IMU biases at the start: " << describe(start_biases_) << std::endl;
    bool have_frame = true;
    while (have_frame)
    {
        trackFrame(f);
        const int max_frames = options_.tracker.max_frames;
        have_frame = (max_frames <= 0 || int(history_.size()) < max_frames) && nextFrame(f);
        if (!have_frame) finishSearch(f, have_frame);
    }
    if (search_ && search_->searching())
    {
        const double last_verified_t = monitor_.lastVerifiedT();
        summary_.longest_unverified_s = std::max(summary_.longest_unverified_s, f.timestamp - last_verified_t);
        summary_.longest_wait_s = std::max(summary_.longest_wait_s, f.timestamp - last_verified_t);
        out_ << "the frames ended during a relocalization search (unverified since t " << std::fixed
             << std::setprecision(3) << last_verified_t << ")" << std::endl;
    }
    monitor_.ended();
    summary_.frames = history_.size();
    summary_.map = context_.figures();
    summary_.localizer_setup_s = starter_ ? starter_->setupSeconds() : 0;
    return summary_;
}

void TrackingSession::finishSearch(dataset::StereoFrame& f, bool& have_frame)
{
    if (!search_ || !search_->searching()) return;
    // The frames ended with the search behind: let it finish them (a restart then tracks them again).
    if (const auto found = search_->finish()) settle(*found, f.timestamp);
    have_frame = nextFrame(f);
}

void TrackingSession::trackFrame(dataset::StereoFrame& f)
{
    TrackStep step = tracker_->step(f, monitor_.stereoGate());
    FrameReport& r = step.report;
    r.lost = monitor_.lostByMisses(r);
    // The frame's place in the trajectory: a restart forgets the poses after its fix, so frames tracked again
    // take the numbers they had.
    const size_t number = history_.size() + 1;
    monitor_.frameTracked(r);
    double ms_check = 0, ms_search = 0;
    const double explained = checkTrack(f, step, number, ms_check);
    latest_ = step.estimate;
    if (frame_hook_) frame_hook_(r, *this);
    keepImuSinceVerified(f);
    if (relocalize(f, r, ms_search)) return;  // this frame is among those tracked again
    log_.addFrame(f, r, explained, ms_check, ms_search);
    history_.add(r.t, r.T_world_cam0);
    recordTiming(r, ms_check, ms_search);
    if (number % 50 == 0)
    {
        out_ << "frame " << number << ": " << toString(monitor_.health());
        if (log_.hasGroundTruth())
            out_ << ", error " << std::fixed << std::setprecision(3) << log_.lastErrorM() << " m";
        out_ << std::endl;
    }
}

double TrackingSession::checkTrack(const dataset::StereoFrame& f, const TrackStep& step, size_t number, double& ms)
{
    if (!search_ || !monitor_.checkDue(number)) return NAN;
    const FrameReport& r = step.report;
    const auto t0 = std::chrono::steady_clock::now();
    const auto c = starter_->checkTrack(f, r.T_world_cam0, monitor_.checkAlignsBelow(), step.denseCloud());
    ms = msSince(t0);
    const CheckOutcome outcome = monitor_.checked(r, {c.explained, c.refined, c.refined_explained});
    if (c.refined)
        out_ << "check at t " << std::fixed << std::setprecision(3) << r.t << ": explained " << c.explained << ", "
             << c.refined_explained << " after aligning (moved " << c.moved_m << " m, " << c.moved_deg
             << " deg): " << toString(outcome) << std::endl;
    return c.explained;
}

void TrackingSession::restartTrackerAt(double t, const Eigen::Isometry3d& T_world_cam0)
{
    latest_ = tracker_->initialize(t, T_world_cam0, latest_.state.v_map, latest_.biasPrior(), nullptr);
}

bool TrackingSession::relocalize(const dataset::StereoFrame& f, const FrameReport& r, double& ms)
{
    if (!search_) return false;
    const RelocalizationOptions& o = options_.relocalization;
    if (monitor_.lossDue(r))
    {
        // Lost (lost_after_misses rejected alignments, or the stereo geometry fits the map better elsewhere):
        // global localization looks for a start in the next frames on its own thread while the tracker tracks
        // on, so a loss that was a false alarm (the view merely poorly explained) costs nothing.
        ++summary_.losses;
        monitor_.searchBegun();
        odometry_diverged_ = false;
        const double last_verified_t = monitor_.lastVerifiedT();
        out_ << "lost at t " << std::fixed << std::setprecision(3) << r.t << ": relocalizing" << std::endl;
        std::optional<SearchPrior> prior;
        if (o.relocalize_near_m > 0)
            if (const auto known = history_.at(last_verified_t))
                prior = SearchPrior{known->translation(), last_verified_t, o.relocalize_near_m, o.relocalize_speed_m_s};
        starter_->setBiasPrior(latest_.biasPrior());
        search_->begin("reloc " + std::to_string(summary_.losses), prior, o.relocalize_single_fix, headingPrior(r.t));
    }
    if (!search_->searching()) return false;
    // Only the hand-over counts in the frame's time: the search itself runs beside the tracker.
    const auto t0 = std::chrono::steady_clock::now();
    since_loss_.emplace_back(f, latest_.state);
    search_->push(f, odometryPrediction(r));
    const auto found = search_->poll();
    ms = msSince(t0);
    return found && settle(*found, r.t);
}

std::optional<OdometryPrediction> TrackingSession::odometryPrediction(const FrameReport& r)
{
    const RelocalizationOptions& o = options_.relocalization;
    if (o.relocalize_odometry_drift_ratio <= 0 || odometry_diverged_) return std::nullopt;
    // A track faster than the platform goes has diverged (the IMU alone over a view without landmarks, and a
    // window too sure of its velocity to take them back): its place is no prediction, and a place near it no
    // answer, for the rest of the loss.
    const double speed = latest_.state.v_map.norm(), max_speed = options_.tracker.initialization.init_max_speed_m_s;
    if (speed > max_speed)
    {
        odometry_diverged_ = true;
        out_ << "odometry at t " << std::fixed << std::setprecision(3) << r.t << ": the lost track moves at "
             << std::setprecision(1) << speed << " m/s (> " << max_speed
             << "): the search goes on without its prediction" << std::endl;
        return std::nullopt;
    }
    // The track runs on from the last verified pose (a restart forgets the poses after its fix): its position is
    // that pose carried by the odometry, and its path since is what the odometry's error grows with.
    double path_m = history_.pathLengthSince(monitor_.lastVerifiedT());
    if (const auto last = history_.last()) path_m += (r.T_world_cam0.translation() - last->translation()).norm();
    return OdometryPrediction{r.T_world_cam0.translation(),
                              o.relocalize_odometry_floor_m + o.relocalize_odometry_drift_ratio * path_m};
}

void TrackingSession::keepImuSinceVerified(const dataset::StereoFrame& f)
{
    for (const dataset::ImuSample& s : f.imu)
        if (imu_since_verified_.empty() || s.t > imu_since_verified_.back().t) imu_since_verified_.push_back(s);
    const double t_verified = monitor_.lastVerifiedT();
    while (!imu_since_verified_.empty() && imu_since_verified_.front().t < t_verified) imu_since_verified_.pop_front();
}

std::optional<HeadingPrior> TrackingSession::headingPrior(double t_loss) const
{
    const RelocalizationOptions& o = options_.relocalization;
    const double t_verified = monitor_.lastVerifiedT();
    const auto T_world_cam0 = history_.at(t_verified);
    if (o.relocalize_heading_margin_deg <= 0 || !T_world_cam0) return std::nullopt;
    HeadingPrior h;
    h.R_world_body = T_world_cam0->linear() * T_body_cam_.linear().transpose();
    h.t = t_verified;
    h.margin_deg = o.relocalize_heading_margin_deg;
    h.t_until = t_loss + o.relocalize_heading_for_s;
    h.imu.assign(imu_since_verified_.begin(), imu_since_verified_.end());
    return h;
}

bool TrackingSession::settle(const GlobalInitialState& found, double t_now)
{
    const double t_fix = found.anchor.timestamp;
    const double last_verified_t = monitor_.lastVerifiedT();
    summary_.longest_unverified_s = std::max(summary_.longest_unverified_s, t_fix - last_verified_t);
    summary_.longest_wait_s = std::max(summary_.longest_wait_s, t_now - last_verified_t);
    const auto tracked = history_.at(t_fix);
    const TrackerOptions& o = options_.tracker;
    const bool agrees = tracked && core::translationDistance(*tracked, found.T_world_cam0) <= o.max_correction_m &&
                        core::rotationDistanceRad(*tracked, found.T_world_cam0) * 180 / M_PI <= o.max_correction_deg;
    out_ << "relocalization at t " << std::fixed << std::setprecision(3) << t_fix << ": unverified since t "
         << last_verified_t << ", found at t " << t_now << "; "
         << (agrees ? "the fixes confirm the track: loss withdrawn" : "restarted") << std::endl;
    monitor_.fixFound(t_fix, agrees);
    if (agrees)
    {
        ++summary_.withdrawn;
        since_loss_.clear();
        return false;
    }
    ++summary_.relocalizations;
    estimation::FrameState track_at_fix = latest_.state;
    for (const auto& [frame, state] : since_loss_)
        if (frame.timestamp <= t_fix) track_at_fix = state;
    // A single fix brings no velocity: the track's, turned into the fix's frame.
    const Eigen::Vector3d v_world =
        found.v_world ? *found.v_world
                      : velocityAtFix(found.T_world_cam0, T_body_cam_, track_at_fix.T_map_body, track_at_fix.v_map);
    // The biases the track had at the fix, with its present uncertainty about them.
    ImuBiasPrior biases = latest_.biasPrior();
    biases.gyro_bias = track_at_fix.gyro_bias;
    biases.acc_bias = track_at_fix.acc_bias;
    latest_ = tracker_->initializeFromGlobal(t_fix, found.T_world_cam0, v_world, biases, &found.anchor);
    log_.rewindTo(t_fix);
    history_.forgetFrom(t_fix);
    log_.addStart(found.anchor, found.T_world_cam0);
    history_.add(t_fix, found.T_world_cam0);
    // The frames after the fix are tracked again from it, before any unread frame.
    std::deque<dataset::StereoFrame> again;
    for (auto& [frame, state] : since_loss_)
        if (frame.timestamp > t_fix) again.push_back(std::move(frame));
    queued_.insert(queued_.begin(), std::make_move_iterator(again.begin()), std::make_move_iterator(again.end()));
    since_loss_.clear();
    return true;
}

}  // namespace quasiloc::tracking
