#include <mrpt/system/CTicTac.h>

#include <Eigen/Dense>
#include <cmath>
#include <memory>
#include <optional>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <algorithm>
#include <quasiloc/core/error.h>
#include <quasiloc/core/ordered_tasks.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/worker_thread.h>
#include <quasiloc/tracking/map_points.h>
#include <quasiloc/tracking/tracker.h>

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
}  // namespace

Tracker::Tracker(const TrackerOptions& options, const estimation::MapRefinementOptions& refinement,
                 const estimation::EstimatorOptions& estimator, const estimation::ReweightingOptions& reweighting,
                 const core::StereoRig& rig, const estimation::ImuNoise& imu_noise, quasi::QuasiRenderer& renderer,
                 frontend::Frontend& frontend)
    : options_(options),
      estimator_(estimator),
      reweighting_(reweighting),
      imu_noise_(imu_noise),
      refiner_(refinement, renderer, frontend),
      map_(renderer.map()),
      frontend_(frontend),
      right_frontend_(std::make_unique<frontend::Frontend>(frontend.options())),
      stereo_matcher_(rig, frontend.options().stereo),
      rig_(rig)
{
    // Options set in code (a library caller) meet the same ranges as loaded ones.
    options_.checkRanges("Tracker", "Tracking");
    options_.initialization.checkRanges("Tracker", "Initialization");
    options_.factors.check("Tracker");
    core::require(refinement.direct.model_block_px % options_.model_downscale == 0, "Tracker: [Tracking] model_downscale",
                  std::to_string(options_.model_downscale) + " does not divide [DirectAlignment] model_block_px (" +
                      std::to_string(refinement.direct.model_block_px) + ")");
    (void)rig.left.downscaled(options_.model_downscale);  // InputError now, not at the first keyframe
    stereo_check_bound_ = options_.factors.stereo_check_max_sigmas;
    if (options_.map_term == MapTerm::Auto)
    {
        // A map without reflectivity (constant) offers the edge term only its depth discontinuities.
        const auto [lo, hi] = map_.reflectivityRange();
        options_.map_term = hi - lo > 1e-3f ? MapTerm::Factor : MapTerm::None;
    }
    estimator_.check("Tracker");
    reweighting_.check("Tracker");
    T_body_cam_ = core::toIsometry(rig.T_body_left);
    stereo_.left = estimation::CameraGeometry{rig.left, T_body_cam_};
    stereo_.right = rig.right;
    stereo_.T_left_right = core::toIsometry(rig.T_left_right);
    if (options_.factors.map_planes) plane_associator_ = std::make_unique<MapPlaneAssociator>(rig.left, MapPlaneOptions{});
    if (options_.factors.map_lines)
    {
        line_extractor_ = std::make_unique<MapLineExtractor>(stereo_.left.model, mapLineOptions(), frontend.options().lines);
        line_detector_ = std::make_unique<frontend::LineDetector>(frontend.options().lines);
    }
}

void Tracker::setStereoCloud(const reloc::StereoCloud* cloud)
{
    stereo_cloud_ = cloud;
    guided_stereo_.reset();
    if (cloud && options_.stereo_matching == StereoMatching::Guided)
        guided_stereo_ = std::make_unique<GuidedStereo>(rig_, cloud->rectification(), frontend_.options().stereo,
                                                        options_.guided);
}

MapLineOptions Tracker::mapLineOptions() const
{
    MapLineOptions lo;
    lo.max_angle_deg = options_.factors.line_max_angle_deg;
    lo.max_candidates = options_.factors.line_max_candidates;
    return lo;
}

std::vector<frontend::LineSegment> Tracker::cameraLines(const cv::Mat& image) const
{
    cv::Mat gray = image;
    if (gray.channels() == 3) cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
    return line_detector_->detect(gray);
}

Tracker::~Tracker() = default;

void Tracker::initialize(double t, const Eigen::Isometry3d& T_world_cam0, const Eigen::Vector3d& v_world,
                         const ImuBiasPrior& biases, const dataset::StereoFrame* frame)
{
    start(t, T_world_cam0, v_world, frame, options_.initialization.init_sigma_m, options_.initialization.init_sigma_deg, options_.initialization.init_sigma_v, biases);
}

void Tracker::initializeFromGlobal(double t, const Eigen::Isometry3d& T_world_cam0, const Eigen::Vector3d& v_world,
                                   const ImuBiasPrior& biases, const dataset::StereoFrame* frame)
{
    start(t, T_world_cam0, v_world, frame, options_.initialization.init_global_sigma_m, options_.initialization.init_global_sigma_deg,
          options_.initialization.init_global_sigma_v, biases);
}

namespace
{
/** Per-axis sigmas of the marginal's gyroscope and accelerometer bias blocks. */
void biasSigmas(const estimation::StatePrior& prior, Eigen::Vector3d& gyro, Eigen::Vector3d& acc)
{
    const Eigen::Matrix<double, 15, 15> cov = prior.information.ldlt().solve(Eigen::Matrix<double, 15, 15>::Identity());
    gyro = cov.diagonal().segment<3>(9).cwiseMax(0).cwiseSqrt();
    acc = cov.diagonal().segment<3>(12).cwiseMax(0).cwiseSqrt();
}
}  // namespace

void Tracker::applyStandstill(const StaticImuEstimate& still)
{
    // A standing platform: velocity zero to within the vibration's sway, gyroscope bias as measured. The blocks'
    // correlations with the rest of the state are dropped (their new values come from the IMU alone).
    constexpr double kStandingSigmaV = 0.01;  // m/s
    const auto setBlock = [this](int first, double sigma) {
        prior_.information.middleRows(first, 3).setZero();
        prior_.information.middleCols(first, 3).setZero();
        prior_.information.block<3, 3>(first, first) = Eigen::Matrix3d::Identity() / (sigma * sigma);
    };
    state_.v_map.setZero();
    state_.gyro_bias = still.gyro_bias;
    prior_.mean.v_map.setZero();
    prior_.mean.gyro_bias = still.gyro_bias;
    setBlock(6, kStandingSigmaV);
    setBlock(9, still.gyro_bias_sigma);
}

ImuBiasPrior Tracker::biasPrior() const
{
    ImuBiasPrior p;
    p.gyro_bias = state_.gyro_bias;
    p.acc_bias = state_.acc_bias;
    Eigen::Vector3d sg, sa;
    biasSigmas(prior_, sg, sa);
    p.gyro_sigma = sg.maxCoeff();
    p.acc_sigma = sa.maxCoeff();
    p.source = "the track's estimate";
    return p;
}

void Tracker::start(double t, const Eigen::Isometry3d& T_world_cam0, const Eigen::Vector3d& v_world,
                    const dataset::StereoFrame* frame, double sigma_m, double sigma_deg, double sigma_v,
                    const ImuBiasPrior& biases)
{
    core::require(T_world_cam0.matrix().allFinite() && v_world.allFinite(), "Tracker::initialize",
                  "initial pose or velocity is not finite");
    core::require(biases.gyro_bias.allFinite() && biases.acc_bias.allFinite() && biases.gyro_sigma > 0 &&
                      biases.acc_sigma > 0,
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
    prev_stereo_.clear();
    prev_stereo_of_left_.clear();
    if (frame && options_.temporal_landmarks)
    {
        std::vector<estimation::TemporalLandmark> none;
        temporalLandmarks(extractStereo(*frame), t, none);
    }
    initialized_ = true;
}

std::vector<MapLine> Tracker::quasiImageLines(FrameReport& rep) const
{
    mrpt::system::CTicTac tic;
    // Lines of the quasi-image the alignment rendered at the prediction, lifted at its pose.
    const quasi::QuasiImage& q = refiner_.quasiImage();
    std::vector<MapLine> lines = line_extractor_->mapLines(q.depth, core::toIsometry(q.T_world_cam));
    rep.map_lines = int(lines.size());
    rep.ms_lines = tic.Tac() * 1e3;
    return lines;
}

void Tracker::addMapLines(const std::vector<frontend::LineSegment>& camera_lines, const std::vector<MapLine>& map_lines,
                          const Eigen::Isometry3d& T_world_cam, double sigma_m, double sigma_rad,
                          estimation::WindowInput& in, FrameReport& rep)
{
    mrpt::system::CTicTac tic;
    const core::CameraModel& camera = stereo_.left.model;
    const MapLineOptions lo = mapLineOptions();
    // The association window from the pose covariance: the predicted pixel sigma at the map lines' median depth.
    std::vector<double> depths;
    const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();
    for (const MapLine& m : map_lines) depths.push_back((T_cam_world * m.point).z());
    const double depth = std::max(0.3, estimation::medianDepth(depths, 2.0));
    rep.line_window_px = std::clamp(options_.factors.line_window_sigmas * camera.fx * (sigma_rad + sigma_m / depth),
                                    options_.factors.line_window_min_px, options_.factors.line_window_max_px);
    in.lines = associateMapLines(camera_lines, map_lines, camera, T_world_cam, rep.line_window_px,
                                 options_.factors.line_sigma_px, lo);
    rep.camera_lines = int(camera_lines.size());
    rep.line_factors = int(in.lines.size());
    size_t candidates = 0;
    for (const auto& l : in.lines) candidates += l.candidates.size();
    rep.line_candidates = in.lines.empty() ? 0 : double(candidates) / double(in.lines.size());
    rep.ms_lines += tic.Tac() * 1e3;
}

void Tracker::addMapPoints(const frontend::FrameFeatures& camera, const Eigen::Isometry3d& T_world_cam, estimation::WindowInput& in, FrameReport& rep)
{
    mrpt::system::CTicTac tic;
    const quasi::QuasiImage& q = refiner_.quasiImage();
    frontend::FrameFeatures fq;
    frontend_.extractPoints(refiner_.quasiFeatureImage(), q.valid, fq);
    MapPointOptions po;
    po.window_px = options_.factors.point_window_px;
    po.sigma_px = options_.factors.point_sigma_px;
    po.lift_radius_px = refiner_.options().lift_radius_px;
    in.points = associateMapPoints(camera.points, fq.points, q, map_, stereo_.left.model, T_world_cam,
                                   frontend_.options().point_matching, po);
    rep.quasi_keypoints = int(fq.points.keypoints.size());
    rep.point_factors = int(in.points.size());
    rep.ms_points = tic.Tac() * 1e3;
}

void Tracker::addMapPlanes(const StereoPoints& points, const Eigen::Isometry3d& T_world_cam,
                           estimation::WindowInput& in, FrameReport& rep) const
{
    mrpt::system::CTicTac tic;
    std::vector<Eigen::Vector3d> p_cam;
    std::vector<double> sigma;
    mapPointsWithSigma(points, p_cam, sigma);
    // All points together count as plane_effective_points independent observations (neighbouring points share the
    // map's and the stereo's errors), as in the stereo map factor.
    const double scale = std::sqrt(std::max(1.0, double(p_cam.size()) / options_.factors.plane_effective_points));
    for (double& s : sigma) s *= scale;
    in.planes = plane_associator_->associate(p_cam, sigma, refiner_.quasiImage(), T_world_cam);
    rep.plane_factors = int(in.planes.size());
    size_t candidates = 0;
    for (const auto& f : in.planes) candidates += f.candidates.size();
    rep.plane_candidates = in.planes.empty() ? 0 : double(candidates) / double(in.planes.size());
    rep.ms_planes = tic.Tac() * 1e3;
}

void Tracker::mapPointsWithSigma(const StereoPoints& points, std::vector<Eigen::Vector3d>& p_cam,
                                 std::vector<double>& sigma_m) const
{
    const double fb = stereo_.left.model.fx * stereo_.T_left_right.translation().norm();
    for (const frontend::StereoPoint& s : points.stereo)
    {
        const double z = s.p_left.z();
        if (z < 0.2 || z > options_.factors.stereo_map_max_depth_m || !s.p_left.allFinite()) continue;
        const double depth_sigma = z * z / fb * options_.factors.stereo_disparity_sigma_px;
        p_cam.push_back(s.p_left);
        sigma_m.push_back(std::hypot(options_.factors.stereo_map_sigma_m, depth_sigma));
    }
}

void Tracker::stereoMapPoints(const StereoPoints& points, std::vector<Eigen::Vector3d>& p_cam,
                              std::vector<double>& sigma_m) const
{
    if (!denseStereo()) return mapPointsWithSigma(points, p_cam, sigma_m);
    for (const Eigen::Vector3f& p : points.dense)
    {
        if (p.z() > options_.factors.stereo_map_max_depth_m) continue;
        p_cam.push_back(p.cast<double>());
        sigma_m.push_back(std::hypot(options_.factors.stereo_map_sigma_m, stereo_cloud_->depthSigma(p.z())));
    }
}

void Tracker::addStereoMapTerm(const StereoPoints& points, estimation::WindowInput& in) const
{
    estimation::MapDistanceTerm term;
    term.field = distance_field_;
    term.effective_points = options_.factors.stereo_map_effective_points;
    term.truncation_m = options_.factors.stereo_map_truncation_m;
    stereoMapPoints(points, term.p_cam, term.sigma_m);
    if (term.p_cam.size() >= 10) in.map_distance_terms.push_back(std::move(term));
}

bool Tracker::edgesAsUsual(const FrameReport& r) const
{
    const double usual = edge_inlier_ratio_usual_;
    return std::isnan(usual) || r.edge_inlier_ratio >= options_.factors.stereo_check_min_edge_ratio * usual;
}

bool Tracker::checkStereoAgainstMap(const StereoPoints& points, const MapAlignment& a, FrameReport& rep)
{
    // The pose of an accepted map alignment (set with T_map_body): it rests on the left image alone.
    if (!a.T_map_body || !distance_field_ || !options_.temporal_landmarks) return true;
    const Eigen::Isometry3d T_world_cam_edges = *a.T_map_body * T_body_cam_;
    std::vector<Eigen::Vector3d> p_cam;
    std::vector<double> sigma_m;
    stereoMapPoints(points, p_cam, sigma_m);
    if (p_cam.size() < 10) return true;
    // The median, not the mean: clutter that the map lacks (people, moved objects) is far from every surface.
    std::vector<double> sigmas(p_cam.size());
    for (size_t i = 0; i < p_cam.size(); ++i)
        sigmas[i] = distance_field_->distance((T_world_cam_edges * p_cam[i]).cast<float>()) / sigma_m[i];
    std::nth_element(sigmas.begin(), sigmas.begin() + long(sigmas.size() / 2), sigmas.end());
    rep.stereo_map_sigmas = sigmas[sigmas.size() / 2];
    // The check trusts the edge-aligned pose only when the edges fit as well as they usually do: aligned from a wrong
    // pose (a restart, a kidnap, the end of a gap) the alignment settles in a poorer optimum, and then the stereo,
    // not the pose, is the one to believe.
    const double usual = edge_inlier_ratio_usual_;
    const bool edges_as_usual = edgesAsUsual(rep);
    rep.stereo_rejected = edges_as_usual && stereo_check_bound_ > 0 && rep.stereo_map_sigmas > stereo_check_bound_;
    if (edges_as_usual && !rep.stereo_rejected)
        edge_inlier_ratio_usual_ = std::isnan(usual) ? rep.edge_inlier_ratio : 0.95 * usual + 0.05 * rep.edge_inlier_ratio;
    return !rep.stereo_rejected;
}

// Points only: the stereo and temporal matching use no line, so the front-end's line branch is skipped.
void Tracker::extractLeftPoints(const dataset::StereoFrame& frame, StereoPoints& sp)
{
    frontend_.extractPoints(frame.left, cv::Mat(), sp.left);
}

void Tracker::extractRightPoints(const dataset::StereoFrame& frame, StereoPoints& sp)
{
    right_frontend_->extractPoints(frame.right, cv::Mat(), sp.right);
}

void Tracker::matchStereoPoints(StereoPoints& sp) const
{
    if (guidedStereo())
        sp.stereo = guided_stereo_->match(sp.left.points.keypoints, sp.disparity, sp.right.points.keypoints);
    else
        sp.stereo = stereo_matcher_.match(sp.left.points, sp.right.points);
    sp.stereo_of_left.assign(sp.left.points.size(), -1);
    for (size_t k = 0; k < sp.stereo.size(); ++k) sp.stereo_of_left[size_t(sp.stereo[k].left)] = int(k);
}

void Tracker::matchTemporal(StereoPoints& sp, double t) const
{
    sp.temporal.clear();
    // The temporal matching looks for a keypoint within temporal_window_px of where it was: across a gap (dropped
    // frames) the camera has moved farther than that, and what it matches there are other points.
    if (prev_stereo_.empty() || t - prev_stereo_t_ > options_.temporal_max_gap_s) return;
    frontend::PointMatchingOptions pm = frontend_.options().point_matching;
    pm.window_px = options_.temporal_window_px;
    sp.temporal = frontend::matchPoints(prev_left_.points, sp.left.points, pm);
}

void Tracker::matchFramePoints(StereoPoints& sp, double t) const
{
    matchStereoPoints(sp);
    matchTemporal(sp, t);
}

void Tracker::extractDisparity(const dataset::StereoFrame& frame, StereoPoints& sp) const
{
    if (!denseStereo()) return;
    sp.disparity = stereo_cloud_->disparity(frame.left, frame.right, "frame " + std::to_string(frame.index));
}

void Tracker::extractDenseCloud(StereoPoints& sp) const
{
    if (!denseStereo()) return;
    sp.dense = stereo_cloud_->points(sp.disparity);
}

Tracker::StereoPoints Tracker::extractStereo(const dataset::StereoFrame& frame)
{
    StereoPoints sp;
    extractLeftPoints(frame, sp);
    if (!guidedStereo()) extractRightPoints(frame, sp);
    extractDisparity(frame, sp);
    extractDenseCloud(sp);
    matchFramePoints(sp, frame.timestamp);
    return sp;
}

void Tracker::temporalLandmarks(StereoPoints current, double t, std::vector<estimation::TemporalLandmark>& out)
{
    const frontend::FrameFeatures& left = current.left;
    const frontend::FrameFeatures& right = current.right;
    const Eigen::Isometry3d T_map_cam_prev = state_.T_map_body * T_body_cam_;
    const auto px = [](const cv::KeyPoint& k) { return Eigen::Vector2d(k.pt.x, k.pt.y); };
    for (const frontend::PointMatch& m : current.temporal)
    {
        const int a = prev_stereo_of_left_[size_t(m.query)], b = current.stereo_of_left[size_t(m.train)];
        if (a < 0 || b < 0) continue;
        const frontend::StereoPoint &sp = prev_stereo_[size_t(a)], &sc = current.stereo[size_t(b)];
        estimation::TemporalLandmark lm;
        lm.p_map_guess = T_map_cam_prev * sp.p_left;
        lm.previous = {px(prev_left_.points.keypoints[size_t(sp.left)]), px(prev_right_keypoints_[size_t(sp.right)])};
        lm.current = {px(left.points.keypoints[size_t(sc.left)]), px(right.points.keypoints[size_t(sc.right)])};
        out.push_back(lm);
        if (int(out.size()) >= options_.max_landmarks) break;
    }
    prev_stereo_t_ = t;
    prev_left_ = std::move(current.left);
    prev_right_keypoints_ = std::move(current.right.points.keypoints);
    prev_stereo_ = std::move(current.stereo);
    prev_stereo_of_left_ = std::move(current.stereo_of_left);
}

bool Tracker::updateStandstill(const dataset::StereoFrame& frame)
{
    if (!standstill_) return false;
    standstill_->add(frame.imu);
    if (standstill_->moved())
    {
        standstill_.reset();
        return false;
    }
    const auto still = standstill_->estimate();
    if (still) applyStandstill(*still);
    return bool(still);
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
    imu.predict(state_.T_map_body, state_.v_map, state_.gyro_bias, state_.acc_bias, predicted.T_map_body, predicted.v_map);
    double sigma_rad = 0, sigma_m = 0;
    predictedSigmas(prior_, imu, sigma_rad, sigma_m);
    rep.prior_sigma_m = std::max(sigma_m, options_.min_prior_sigma_m);
    rep.prior_sigma_deg = std::max(sigma_rad / kDeg, options_.min_prior_sigma_deg);
    rep.ms_predict = tic.Tac() * 1e3;
    return predicted;
}

Tracker::MapAlignment Tracker::alignToMap(const estimation::FrameState& predicted, const dataset::StereoFrame& frame,
                                          estimation::WindowInput& in, FrameReport& rep)
{
    MapAlignment a;
    mrpt::system::CTicTac tic;
    const Eigen::Isometry3d T_world_cam_pred = predicted.T_map_body * T_body_cam_;
    // The quasi-image's encoding is needed by the map point factors alone (features on its gray image).
    const MapFactorOptions& f = options_.factors;
    const int downscale = f.map_points || f.map_lines || f.map_planes ? 1 : options_.model_downscale;
    auto model = refiner_.prepareDirect(stereo_.left.model, T_world_cam_pred, f.map_points, downscale);
    mrpt::system::CTicTac edge_field;
    refiner_.setImage(frame.left, stereo_.left.model, false);
    rep.ms_image = edge_field.Tac() * 1e3;
    const auto r = refiner_.alignPrepared(std::move(model), T_world_cam_pred, rep.prior_sigma_m,
                                          rep.prior_sigma_deg * kDeg);
    rep.ms_align = tic.Tac() * 1e3;
    rep.correction_m = core::translationDistance(r.T_world_cam, T_world_cam_pred);
    rep.correction_deg = core::rotationDistanceRad(r.T_world_cam, T_world_cam_pred) / kDeg;
    rep.edge_inlier_ratio = r.direct.final_inlier_ratio;
    rep.edge_points = r.direct.edge_points;
    // The gate: max_correction_*, or three predicted sigmas when the prediction is less certain than that
    // (after a global initialisation, or after misses): a correction the prediction allows is not an outlier.
    rep.map_update = r.success && rep.correction_m <= std::max(options_.max_correction_m, 3 * rep.prior_sigma_m) &&
                     rep.correction_deg <= std::max(options_.max_correction_deg, 3 * rep.prior_sigma_deg);
    misses_ = rep.map_update ? 0 : misses_ + 1;
    if (!rep.map_update) return a;
    if (f.map_lines || f.map_points || f.map_planes) a.T_world_cam = r.T_world_cam;
    // The edge residuals themselves in the window, linearised from the alignment's pose.
    a.model = r.direct_model;
    estimation::DirectEdgeTerm d;
    d.field = &refiner_.edgeField();
    d.model = a.model.get();
    d.camera = &stereo_.left.model;
    d.sigma_px = f.direct_factor_sigma_px;
    d.effective_points = f.direct_factor_effective_points;
    d.truncation_px = refiner_.options().direct.truncation_px;
    d.huber_px = refiner_.options().direct.huber_px;
    in.direct_terms.push_back(d);
    a.T_map_body = r.T_world_cam * T_body_cam_.inverse();
    return a;
}

void Tracker::addVisualTerms(StereoPoints stereo_points, const std::vector<frontend::LineSegment>& camera_lines,
                             const std::vector<MapLine>& map_lines, const MapAlignment& a, bool stereo_ok,
                             estimation::WindowInput& in, FrameReport& rep)
{
    const MapFactorOptions& f = options_.factors;
    if (a.T_world_cam && f.map_planes && options_.temporal_landmarks && stereo_ok)
        addMapPlanes(stereo_points, *a.T_world_cam, in, rep);
    if (a.T_world_cam && f.map_points && options_.temporal_landmarks)
        addMapPoints(stereo_points.left, *a.T_world_cam, in, rep);
    if (a.T_world_cam && f.map_lines)
        addMapLines(camera_lines, map_lines, *a.T_world_cam, rep.prior_sigma_m, rep.prior_sigma_deg * kDeg, in, rep);
    if (options_.temporal_landmarks && options_.map_updates && f.stereo_map_factor && distance_field_ && stereo_ok)
        addStereoMapTerm(stereo_points, in);
    rep.stereo_map_points = in.map_distance_terms.empty() ? 0 : int(in.map_distance_terms[0].p_cam.size());
    last_dense_ = std::move(stereo_points.dense);
    if (options_.temporal_landmarks && stereo_ok) temporalLandmarks(std::move(stereo_points), rep.t, in.landmarks);
    else if (!stereo_ok)
    {
        // Its stereo pairs would be the next frame's landmarks: they start again from the next good frame.
        prev_stereo_.clear();
        prev_stereo_of_left_.clear();
    }
    rep.landmarks = int(in.landmarks.size());
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

FrameReport Tracker::track(const dataset::StereoFrame& frame)
{
    core::require(initialized_, "Tracker::track", "initialize() must be called first");
    const std::string input = "frame " + std::to_string(frame.index) + " (t = " + std::to_string(frame.timestamp) + ")";
    core::require(frame.timestamp > state_.t, input, "timestamp does not increase");
    core::require(!frame.imu.empty(), input, "no IMU sample since the previous frame");
    mrpt::system::CTicTac total, tic;
    FrameReport rep;
    rep.t = frame.timestamp;

    // 1. IMU prediction (after a standstill since the start, from its bias and zero velocity).
    rep.standing = updateStandstill(frame);
    estimation::ImuPreintegration imu(imu_noise_, state_.gyro_bias, state_.acc_bias);
    const estimation::FrameState predicted = predict(frame, imu, rep);

    // The frame's stereo tasks, in the order they are claimed: the left image's points (temporal landmarks and the map
    // factors on them), the dense disparity (stereo_map_points = dense), the right image's points (descriptor
    // matching), then the temporal matching, the stereo matching, the dense cloud from the disparity, and the
    // camera's segments (map_lines). With concurrent_stages the worker thread runs them while this one renders the
    // map at the prediction, computes the camera's edge field and runs the alignment; this one runs what is left
    // after that. Who runs a task changes its timing only.
    // Why this split: ORB (about 4.5 ms) and the dense stereo (about 6 ms) are single-threaded for the most part and
    // only the window needs them; the alignment needs the render, the edge model and the edge field (parallel
    // loops, about 10 ms together). Shared in claiming order, the two long serial tasks often ended up one after the
    // other on this thread while the worker, done with the edge field, waited (docs/experiments.md, seventh round).
    estimation::WindowInput in;
    rep.keyframe = options_.map_updates && options_.map_term != MapTerm::None &&
                   frames_ % size_t(options_.keyframe_every) == 0;
    core::OrderedTasks tasks;
    StereoPoints stereo_points;
    if (options_.temporal_landmarks)
    {
        StereoPoints& sp = stereo_points;
        const size_t left = tasks.add([this, &frame, &sp] { extractLeftPoints(frame, sp); });
        std::vector<size_t> stereo_inputs{left};
        const bool dense = denseStereo();
        const size_t disparity = dense ? tasks.add([this, &frame, &sp] { extractDisparity(frame, sp); }) : 0;
        if (dense) stereo_inputs.push_back(disparity);
        if (!guidedStereo())
            stereo_inputs.push_back(tasks.add([this, &frame, &sp] { extractRightPoints(frame, sp); }));
        // Each consumer after its inputs (earlier tasks, so already claimed when it is). Three small tasks rather
        // than one: whichever thread is free first takes the next, so the tracking thread, done with the
        // alignment, shares what the worker has left instead of waiting for it.
        tasks.add([this, &tasks, &frame, &sp, left] {
            tasks.wait(left);
            matchTemporal(sp, frame.timestamp);
        });
        tasks.add([this, &tasks, &sp, stereo_inputs] {
            for (size_t i : stereo_inputs) tasks.wait(i);
            matchStereoPoints(sp);
        });
        if (dense)
            tasks.add([this, &tasks, &sp, disparity] {
                tasks.wait(disparity);
                extractDenseCloud(sp);
            });
    }
    std::vector<frontend::LineSegment> camera_lines;  // map_lines: the left image's segments
    if (rep.keyframe && options_.factors.map_lines)
        tasks.add([this, &frame, &camera_lines] { camera_lines = cameraLines(frame.left); });
    const bool concurrent = options_.concurrent_stages && cv::getNumThreads() > 1;
    if (concurrent)
    {
        if (!worker_) worker_ = std::make_unique<core::WorkerThread>();
        worker_->start([&tasks] {
            while (tasks.runNext())
            {
            }
        });
    }
    // Whatever happens below, the worker's tasks (which use this frame's locals) end before they do.
    struct WaitAtExit
    {
        core::WorkerThread* w;
        ~WaitAtExit()
        {
            if (w) w->waitForError();
        }
    } wait_at_exit{concurrent ? worker_.get() : nullptr};

    // 2. Map alignment on keyframes (its model stays alive until the window has used it).
    const MapAlignment alignment = rep.keyframe ? alignToMap(predicted, frame, in, rep) : MapAlignment{};
    // The map side of the line factors needs only the quasi-image.
    std::vector<MapLine> map_lines;
    if (alignment.T_world_cam && options_.factors.map_lines) map_lines = quasiImageLines(rep);
    rep.lost = options_.map_updates && misses_ >= options_.lost_after_misses;

    // 3. The frame's stereo points: temporal landmarks (kept for the next frame) and the map factors on them.
    tic.Tic();
    last_dense_.clear();
    tasks.waitAll();
    if (concurrent)
    {
        worker_->wait();
        wait_at_exit.w = nullptr;
    }
    const bool stereo_ok = checkStereoAgainstMap(stereo_points, alignment, rep);
    addVisualTerms(std::move(stereo_points), camera_lines, map_lines, alignment, stereo_ok, in, rep);
    rep.ms_visual = tic.Tac() * 1e3;

    // 4. The two-frame window.
    solveWindow(predicted, imu, alignment, in, rep);
    rep.ms_total = total.Tac() * 1e3;
    return rep;
}

}  // namespace quasiloc::tracking
