#include <mrpt/system/CTicTac.h>

#include <Eigen/Dense>
#include <cmath>
#include <map>
#include <sstream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/map/surface_thickness.h>
#include <quasiloc/tracking/along_track_search.h>
#include <quasiloc/tracking/tracker.h>
#include <quasiloc/tracking/zero_velocity_update.h>

namespace quasiloc::tracking
{
namespace
{
constexpr double kDeg = M_PI / 180.0;

/** RMS per-axis standard deviations (rotation [rad], translation [m]) of the predicted pose: the previous
 *  state's marginal covariance plus the IMU preintegration's, to first order. */
void predictedSigmas(const estimation::StatePrior& prior, const estimation::ImuPreintegration& imu, double& sigma_rad,
                     double& sigma_m)
{
    const Eigen::Matrix<double, 15, 15> cov = prior.information.ldlt().solve(Eigen::Matrix<double, 15, 15>::Identity());
    const double dt = imu.dt();
    // Rotation: previous rotation + preintegrated rotation. Position: previous position, velocity * dt, and the
    // preintegrated position.
    const double var_rot = (cov.block<3, 3>(0, 0).trace() + imu.covariance().block<3, 3>(0, 0).trace()) / 3.0;
    const double var_pos = (cov.block<3, 3>(3, 3).trace() + dt * dt * cov.block<3, 3>(6, 6).trace() +
                            imu.covariance().block<3, 3>(6, 6).trace()) /
                           3.0;
    sigma_rad = std::sqrt(std::max(0.0, var_rot));
    sigma_m = std::sqrt(std::max(0.0, var_pos));
}

/** Per-axis sigmas of the marginal's gyroscope and accelerometer bias blocks. */
void biasSigmas(const estimation::StatePrior& prior, Eigen::Vector3d& gyro, Eigen::Vector3d& acc)
{
    const Eigen::Matrix<double, 15, 15> cov = prior.information.ldlt().solve(Eigen::Matrix<double, 15, 15>::Identity());
    gyro = cov.diagonal().segment<3>(9).cwiseMax(0).cwiseSqrt();
    acc = cov.diagonal().segment<3>(12).cwiseMax(0).cwiseSqrt();
}
}  // namespace

std::vector<estimation::MapDistanceTerm> stereoMapTermsByTruncation(const std::vector<Eigen::Vector3d>& p_cam,
                                                                    const std::vector<double>& sigma_m,
                                                                    double truncation_m, double truncation_sigmas,
                                                                    double effective_points)
{
    core::require(p_cam.size() == sigma_m.size() && truncation_m > 0, "stereoMapTermsByTruncation",
                  "needs one sigma per point and a truncation > 0");
    const double step = std::sqrt(2.0);
    std::map<int, estimation::MapDistanceTerm> by_step;
    for (size_t i = 0; i < p_cam.size(); ++i)
    {
        const double wanted = std::max(truncation_m, truncation_sigmas * sigma_m[i]);
        const int k = std::max(0, int(std::ceil(std::log(wanted / truncation_m) / std::log(step) - 1e-9)));
        estimation::MapDistanceTerm& term = by_step[k];
        term.truncation_m = truncation_m * std::pow(step, k);
        term.p_cam.push_back(p_cam[i]);
        term.sigma_m.push_back(sigma_m[i]);
    }
    std::vector<estimation::MapDistanceTerm> terms;
    for (auto& [k, term] : by_step)
    {
        term.effective_points = by_step.size() == 1
                                    ? effective_points
                                    : effective_points * double(term.p_cam.size()) / double(p_cam.size());
        terms.push_back(std::move(term));
    }
    return terms;
}

double sigmaAlongNormal(const map::DistanceField& field, const Eigen::Isometry3d& T_world_cam,
                        const Eigen::Vector3d& p_cam, double sigma_m, double map_sigma_m)
{
    if (!(sigma_m > map_sigma_m) || !(p_cam.norm() > 0)) return sigma_m;
    // The field is unsigned: on a surface its gradient vanishes. Probed a few voxels off the point along each axis,
    // the steepest gradient is the surface's normal (off a floor, above it; along the floor, none).
    constexpr float kProbe_m = 0.12f;
    const Eigen::Vector3f p = (T_world_cam * p_cam).cast<float>();
    Eigen::Vector3f normal = Eigen::Vector3f::Zero();
    for (int axis = 0; axis < 3; ++axis)
        for (float side : {-1.f, 1.f})
        {
            Eigen::Vector3f g;
            field.distance(p + side * kProbe_m * Eigen::Vector3f::Unit(axis), g);
            if (g.squaredNorm() > normal.squaredNorm()) normal = g;
        }
    if (!(normal.norm() > 0.5f)) return sigma_m;  // no surface within the probes
    const Eigen::Vector3d ray = T_world_cam.linear() * p_cam.normalized();
    const double share = std::abs(normal.cast<double>().normalized().dot(ray));
    const double depth_sigma = std::sqrt(sigma_m * sigma_m - map_sigma_m * map_sigma_m);
    return std::hypot(map_sigma_m, depth_sigma * share);
}

ImuBiasPrior TrackEstimate::biasPrior() const
{
    ImuBiasPrior p;
    p.gyro_bias = state.gyro_bias;
    p.acc_bias = state.acc_bias;
    Eigen::Vector3d sg, sa;
    biasSigmas(marginal, sg, sa);
    p.gyro_sigma = sg.maxCoeff();
    p.acc_sigma = sa.maxCoeff();
    p.source = "the track's estimate";
    return p;
}

const std::vector<Eigen::Vector3f>& TrackStep::denseCloud() const
{
    static const std::vector<Eigen::Vector3f> none;
    return measurement ? measurement->dense : none;
}

Tracker::Tracker(const TrackerOptions& options, const estimation::MapRefinementOptions& refinement,
                 const estimation::EstimatorOptions& estimator, const estimation::ReweightingOptions& reweighting,
                 const core::StereoRig& rig, const estimation::ImuNoise& imu_noise, quasi::QuasiRenderer& renderer,
                 const frontend::FrontendOptions& frontend)
    : options_(options),
      refinement_(refinement),
      estimator_(estimator),
      reweighting_(reweighting),
      imu_noise_(imu_noise),
      renderer_(renderer),
      map_(renderer.map()),
      frontend_options_(frontend),
      rig_(rig),
      measurer_(rig, options, frontend, refinement.direct)
{
    // Options set in code (a library caller) meet the same ranges as loaded ones.
    options_.checkRanges("Tracker", "Tracking");
    options_.initialization.checkRanges("Tracker", "Initialization");
    options_.factors.check("Tracker");
    refinement_.check("Tracker");
    core::require(refinement.direct.model_block_px % options_.model_downscale == 0,
                  "Tracker: [Tracking] model_downscale",
                  std::to_string(options_.model_downscale) + " does not divide [DirectAlignment] model_block_px (" +
                      std::to_string(refinement.direct.model_block_px) + ")");
    (void)rig.left.downscaled(options_.model_downscale);  // InputError now, not at the first keyframe
    if (options_.map_term == MapTerm::Auto) resolveAutoMapTerm();
    estimator_.check("Tracker");
    reweighting_.check("Tracker");
    T_body_cam_ = core::toIsometry(rig.T_body_left);
    stereo_.left = estimation::CameraGeometry{rig.left, T_body_cam_};
    stereo_.right = rig.right;
    stereo_.T_left_right = core::toIsometry(rig.T_left_right);
    if (options_.factors.map_points) quasi_frontend_ = std::make_unique<frontend::Frontend>(frontend);
    if (options_.factors.map_planes)
        plane_associator_ = std::make_unique<MapPlaneAssociator>(rig.left, MapPlaneOptions{});
    if (options_.factors.map_lines)
        line_extractor_ = std::make_unique<MapLineExtractor>(stereo_.left.model, mapLineOptions(), frontend.lines);
}

Tracker::~Tracker() = default;

void Tracker::resolveAutoMapTerm()
{
    // A map without reflectivity (constant) offers the edge term only its depth discontinuities.
    const auto [lo, hi] = map_.reflectivityRange();
    if (hi - lo <= 1e-3f)
    {
        options_.map_term = MapTerm::None;
        map_term_reason_ = "auto: the map's reflectivity is constant";
        return;
    }
    const map::SurfaceThickness thickness = map::measureSurfaceThickness(map_);
    const bool thin = thickness.surface_patches > 0 && thickness.median_m <= options_.edge_map_max_thickness_m;
    options_.map_term = thin ? MapTerm::Factor : MapTerm::None;
    std::ostringstream why;
    why << "auto: the map's reflectivity varies and its surfaces are " << (thin ? "thin" : "thick") << ", "
        << map::describe(thickness) << (thin ? " <= " : " > ") << options_.edge_map_max_thickness_m * 1e3
        << " mm (edge_map_max_thickness_m)";
    map_term_reason_ = why.str();
}

TrackEstimate Tracker::initialize(double t, const Eigen::Isometry3d& T_world_cam0, const Eigen::Vector3d& v_world,
                                  const ImuBiasPrior& biases, const dataset::StereoFrame* frame)
{
    const InitializationOptions& o = options_.initialization;
    return start(t, T_world_cam0, v_world, frame, o.init_sigma_m, o.init_sigma_deg, o.init_sigma_v, biases);
}

TrackEstimate Tracker::initializeFromGlobal(double t, const Eigen::Isometry3d& T_world_cam0,
                                            const Eigen::Vector3d& v_world, const ImuBiasPrior& biases,
                                            const dataset::StereoFrame* frame)
{
    const InitializationOptions& o = options_.initialization;
    return start(t, T_world_cam0, v_world, frame, o.init_global_sigma_m, o.init_global_sigma_deg, o.init_global_sigma_v,
                 biases);
}

void Tracker::applyStandstill(const StaticImuEstimate& still)
{
    // A standing platform: velocity zero to within the vibration's sway, gyroscope bias as measured. The blocks'
    // correlations with the rest of the state are dropped (their new values come from the IMU alone).
    constexpr double kStandingSigmaV = 0.01;  // m/s
    applyZeroVelocity(state_, prior_, kStandingSigmaV);
    state_.gyro_bias = still.gyro_bias;
    prior_.mean.gyro_bias = still.gyro_bias;
    resetBlock(prior_, 9, still.gyro_bias_sigma);
}

void Tracker::measureImageMotion(const FrameMeasurement& m)
{
    image_motion_ = ImageMotion{};
    if (!previous_) return;
    // Standing is judged over at least a third of a second at 30 Hz: frame to frame, a slow run forward hardly
    // moves the keypoints. Moving is seen sooner: a few frames move them by more than their pyramid grid's steps.
    constexpr int kStandingTrackFrames = 10, kMovingTrackFrames = 3;
    constexpr size_t kMinTracks = 10;
    const std::vector<cv::KeyPoint>& before = previous_->left.points.keypoints;
    const std::vector<cv::KeyPoint>& now = m.left.points.keypoints;
    image_motion_.tracked_px =
        keypoint_tracks_.add(previous_.get(), before, &m, now, m.temporal, kStandingTrackFrames, kMinTracks);
    image_motion_.short_tracked_px =
        short_keypoint_tracks_.add(previous_.get(), before, &m, now, m.temporal, kMovingTrackFrames, kMinTracks);
    image_motion_.frame_px = medianImageMotionPx(before, now, m.temporal, kMinTracks);
}

bool Tracker::ImageMotion::moving(double max_px) const
{
    return frame_px > max_px || short_tracked_px > max_px || tracked_px > max_px;
}

bool Tracker::zeroVelocityUpdate(bool imu_standing)
{
    if (!standstill_watch_ || !imu_standing) return false;
    if (!(image_motion_.tracked_px <= options_.zero_velocity_max_motion_px)) return false;
    applyZeroVelocity(state_, prior_, options_.zero_velocity_sigma_m_s);
    return true;
}

TrackEstimate Tracker::start(double t, const Eigen::Isometry3d& T_world_cam0, const Eigen::Vector3d& v_world,
                             const dataset::StereoFrame* frame, double sigma_m, double sigma_deg, double sigma_v,
                             const ImuBiasPrior& biases)
{
    core::require(T_world_cam0.matrix().allFinite() && v_world.allFinite(), "Tracker::initialize",
                  "initial pose or velocity is not finite");
    core::require(
        biases.gyro_bias.allFinite() && biases.acc_bias.allFinite() && biases.gyro_sigma > 0 && biases.acc_sigma > 0,
        "Tracker::initialize", "IMU bias prior is not finite or has a sigma <= 0");
    state_ = estimation::FrameState{};
    state_.gyro_bias = biases.gyro_bias;
    state_.acc_bias = biases.acc_bias;
    state_.t = t;
    state_.T_map_body = T_world_cam0 * T_body_cam_.inverse();
    state_.v_map = v_world;
    prior_.mean = state_;
    Eigen::Matrix<double, 15, 1> sigma;
    sigma << Eigen::Vector3d::Constant(sigma_deg * kDeg), Eigen::Vector3d::Constant(sigma_m),
        Eigen::Vector3d::Constant(sigma_v), Eigen::Vector3d::Constant(biases.gyro_sigma),
        Eigen::Vector3d::Constant(biases.acc_sigma);
    prior_.information = sigma.cwiseInverse().cwiseAbs2().asDiagonal();
    frames_ = 0;
    misses_ = 0;
    standstill_.reset();
    if (options_.initialization.static_initialization) standstill_.emplace(imu_noise_.gyro_noise_density);
    standstill_watch_.reset();
    if (options_.zero_velocity_updates)
        standstill_watch_.emplace(imu_noise_.gyro_noise_density, options_.zero_velocity_span_s);
    keypoint_tracks_ = KeypointTracks{};
    short_keypoint_tracks_ = KeypointTracks{};
    image_motion_ = ImageMotion{};
    previous_.reset();
    if (frame && options_.temporal_landmarks)
    {
        // The start frame's stereo points are the first landmarks' other end.
        std::vector<estimation::TemporalLandmark> none;
        temporalLandmarks(measurer_.measure(*frame, MeasurementRequest{}, nullptr, 0), t, none);
    }
    initialized_ = true;
    return {state_, prior_};
}

void Tracker::temporalLandmarks(std::shared_ptr<const FrameMeasurement> current, double t,
                                std::vector<estimation::TemporalLandmark>& out)
{
    const Eigen::Isometry3d T_map_cam_prev = state_.T_map_body * T_body_cam_;
    const auto px = [](const cv::KeyPoint& k) { return Eigen::Vector2d(k.pt.x, k.pt.y); };
    const FrameMeasurement* prev = previous_.get();
    const std::vector<frontend::PointMatch> none;
    for (const frontend::PointMatch& m : prev ? current->temporal : none)
    {
        const int a = prev->stereo_of_left[size_t(m.query)], b = current->stereo_of_left[size_t(m.train)];
        if (a < 0 || b < 0) continue;
        const frontend::StereoPoint &sp = prev->stereo[size_t(a)], &sc = current->stereo[size_t(b)];
        estimation::TemporalLandmark lm;
        lm.p_map_guess = T_map_cam_prev * sp.p_left;
        lm.previous = {px(prev->left.points.keypoints[size_t(sp.left)]),
                       px(prev->right.points.keypoints[size_t(sp.right)])};
        lm.current = {px(current->left.points.keypoints[size_t(sc.left)]),
                      px(current->right.points.keypoints[size_t(sc.right)])};
        out.push_back(lm);
        if (int(out.size()) >= options_.max_landmarks) break;
    }
    previous_t_ = t;
    previous_ = std::move(current);
}

bool Tracker::updateStandstill(const dataset::StereoFrame& frame)
{
    if (!standstill_) return false;
    standstill_->add(frame.imu);
    // A restart during a steady run reads as standing to the IMU (gravity and vibration alone): the image ends it.
    if (standstill_->moved() || image_motion_.moving(options_.standstill_end_motion_px))
    {
        standstill_.reset();
        return false;
    }
    const auto still = standstill_->estimate();
    if (still) applyStandstill(*still);
    return bool(still);
}

void Tracker::widenVelocityWhileLost(const dataset::StereoFrame& frame, const StereoGate& gate)
{
    const double q = gate.velocity_random_walk;
    if (q > 0) widenVelocity(prior_, q * q * (frame.timestamp - state_.t));
}

estimation::FrameState Tracker::predict(const dataset::StereoFrame& frame, estimation::ImuPreintegration& imu,
                                        FrameReport& rep) const
{
    mrpt::system::CTicTac tic;
    std::vector<estimation::ImuMeasurement> samples;
    samples.reserve(frame.imu.size());
    for (const auto& s : frame.imu) samples.push_back({s.t, s.acc, s.gyro});
    imu.integrateInterval(samples, state_.t, frame.timestamp);
    estimation::FrameState predicted = state_;
    predicted.t = frame.timestamp;
    imu.predict(state_.T_map_body, state_.v_map, state_.gyro_bias, state_.acc_bias, predicted.T_map_body,
                predicted.v_map);
    double sigma_rad = 0, sigma_m = 0;
    predictedSigmas(prior_, imu, sigma_rad, sigma_m);
    rep.prior_sigma_m = std::max(sigma_m, options_.min_prior_sigma_m);
    rep.prior_sigma_deg = std::max(sigma_rad / kDeg, options_.min_prior_sigma_deg);
    rep.ms_predict = tic.Tac() * 1e3;
    return predicted;
}

void Tracker::solveWindow(const estimation::FrameState& predicted, const estimation::ImuPreintegration& imu,
                          const MapAlignment& a, estimation::WindowInput& in, FrameReport& rep)
{
    mrpt::system::CTicTac tic;
    in.stereo = &stereo_;
    in.has_previous = true;
    in.previous = state_;
    in.prior = prior_;
    in.imu = &imu;
    in.current = predicted;
    if (a.T_map_body) in.current.T_map_body = *a.T_map_body;
    estimation::WindowResult result;
    if (estimation::estimateWindow(estimator_, reweighting_, in, result))
    {
        state_ = result.current;
        prior_ = result.marginal;
    }
    else
    {
        // No usable solution: keep the prediction, with the uncertainty the prediction has.
        state_ = predicted;
        prior_.mean = predicted;
    }
    rep.ms_window = tic.Tac() * 1e3;
    rep.ms_window_solve = result.stats.solve_ms;
    rep.ms_window_marginal = result.stats.marginalize_ms;
    ++frames_;
    rep.T_world_cam0 = state_.T_map_body * T_body_cam_;
    rep.gyro_bias = state_.gyro_bias;
    rep.acc_bias = state_.acc_bias;
    biasSigmas(prior_, rep.gyro_bias_sigma, rep.acc_bias_sigma);
}

MeasurementRequest Tracker::request(bool keyframe, const estimation::FrameState& predicted) const
{
    MeasurementRequest r;
    r.points = options_.temporal_landmarks;
    r.edge_field = keyframe;
    r.lines = keyframe && options_.factors.map_lines;
    // The previous measurement is the previous state's frame (temporalLandmarks keeps them together).
    if (options_.temporal_predicted_window && previous_)
        r.T_cam_prevcam = (predicted.T_map_body * T_body_cam_).inverse() * (state_.T_map_body * T_body_cam_);
    return r;
}

TrackStep Tracker::step(const dataset::StereoFrame& frame, const StereoGate& gate)
{
    core::require(initialized_, "Tracker::step", "initialize() must be called first");
    const std::string input = "frame " + std::to_string(frame.index) + " (t = " + std::to_string(frame.timestamp) + ")";
    core::require(frame.timestamp > state_.t, input, "timestamp does not increase");
    core::require(!frame.imu.empty(), input, "no IMU sample since the previous frame");
    mrpt::system::CTicTac total, tic;
    TrackStep result;
    FrameReport& rep = result.report;
    rep.t = frame.timestamp;

    // 1. IMU prediction (after a standstill since the start, from its bias and zero velocity; after a standstill
    // later on, with zero_velocity_updates, from zero velocity; while lost, from a widened velocity).
    widenVelocityWhileLost(frame, gate);
    rep.standing = updateStandstill(frame);
    const bool imu_standing = standstill_watch_ && standstill_watch_->add(frame.imu) && !rep.standing;
    estimation::ImuPreintegration imu(imu_noise_, state_.gyro_bias, state_.acc_bias);
    const estimation::FrameState predicted = predict(frame, imu, rep);
    // A streamed field readies its tiles around the camera on its worker while this frame is measured.
    if (distance_field_) distance_field_->focus(predicted.T_map_body.translation().cast<float>());
    rep.keyframe = gate.map_terms && options_.map_updates && options_.map_term != MapTerm::None &&
                   frames_ % size_t(options_.keyframe_every) == 0;

    // 2. The frame's measurement starts on the measurement stage's thread; meanwhile the map alignment on keyframes
    // (its model stays alive until the window has used it).
    std::unique_ptr<PendingMeasurement> pending =
        measurer_.start(frame, request(rep.keyframe, predicted), previous_, previous_t_);
    estimation::WindowInput in;
    const MapAlignment alignment = rep.keyframe ? alignToMap(predicted, *pending, in, rep) : MapAlignment{};
    rep.alignment_misses = misses_;

    // 3. The frame's measurement: the stereo gate, then the factors on it.
    tic.Tic();
    result.measurement = pending->get();
    const FrameMeasurement& m = *result.measurement;
    if (rep.keyframe) rep.ms_image = m.ms_edge_field;
    measureImageMotion(m);
    if (zeroVelocityUpdate(imu_standing)) rep.standing = true;
    const bool stereo_ok = gateStereo(m, alignment, gate, rep);
    // The window starts from the prediction, or where the search along the street puts it.
    estimation::FrameState start = predicted;
    if (options_.factors.along_track_range_m > 0 && distance_field_ && stereo_ok && gate.map_terms &&
        options_.map_updates)
    {
        std::vector<Eigen::Vector3d> p_cam;
        std::vector<double> sigma_m;
        stereoMapPoints(m, p_cam, sigma_m);
        correctAlongTrack(*distance_field_, options_.factors, T_body_cam_, p_cam, sigma_m, state_, prior_, start,
                          in.pose_measurements);
    }
    in.current = start;  // where the map terms look up the map's normals (solveWindow sets it again)
    addVisualTerms(frame, result.measurement, alignment, stereo_ok, gate.map_terms, in, rep);
    rep.ms_visual = tic.Tac() * 1e3;

    // 4. The two-frame window.
    solveWindow(start, imu, alignment, in, rep);
    result.estimate = {state_, prior_};
    rep.ms_total = total.Tac() * 1e3;
    return result;
}

}  // namespace quasiloc::tracking
