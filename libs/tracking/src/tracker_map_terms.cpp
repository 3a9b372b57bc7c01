// The tracker's map terms: the direct alignment of map edges on keyframes, the stereo gate, and the factors on the
// frame's measurement (tracker.h).
#include <mrpt/system/CTicTac.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <quasiloc/core/pose.h>
#include <quasiloc/quasi/histogram_matching.h>
#include <quasiloc/tracking/crossmodal_points.h>
#include <quasiloc/tracking/edge_trust.h>
#include <quasiloc/tracking/map_points.h>
#include <quasiloc/tracking/tracker.h>

namespace quasiloc::tracking
{
namespace
{
constexpr double kDeg = M_PI / 180.0;
}

Tracker::MapAlignment Tracker::alignToMap(const estimation::FrameState& predicted, PendingMeasurement& measurement,
                                          estimation::WindowInput& in, FrameReport& rep)
{
    MapAlignment a;
    mrpt::system::CTicTac tic;
    const Eigen::Isometry3d T_world_cam_pred = predicted.T_map_body * T_body_cam_;
    const MapFactorOptions& f = options_.factors;
    // The map's edge model reads the planes on blocks only: rendered at a lower resolution, the same blocks cost a
    // fraction of the render's per-pixel work. The structural factors read the full-resolution quasi-image, and the
    // map point factors its encoding (features on its gray image).
    const int downscale = f.map_points || f.map_lines || f.map_planes ? 1 : options_.model_downscale;
    const core::CameraModel render_camera = stereo_.left.model.downscaled(downscale);
    renderer_.render(core::fromIsometry(T_world_cam_pred), render_camera, quasi_, f.map_points,
                     renderer_.options().completionRadiusAt(downscale));
    a.model = std::make_shared<const estimation::DirectAlignmentModel>(
        estimation::buildDirectAlignmentModel(refinement_.direct, quasi_.depth, quasi_.reflectivity, quasi_.valid,
                                              quasi_.sparse, render_camera, T_world_cam_pred, downscale));
    const estimation::CameraEdgeField& field = measurement.edgeField();
    Eigen::Isometry3d T_world_cam = T_world_cam_pred;
    estimation::DirectAlignmentStats stats;
    const double prior_weight = refinement_.direct_prior_weight;
    const estimation::DirectPrior prior{T_world_cam_pred, rep.prior_sigma_m, rep.prior_sigma_deg * kDeg, prior_weight};
    const bool success = estimation::alignDirect(refinement_.direct, field, stereo_.left.model, *a.model, T_world_cam,
                                                 &stats, prior_weight > 0 ? &prior : nullptr);
    rep.ms_align = tic.Tac() * 1e3;
    rep.correction_m = core::translationDistance(T_world_cam, T_world_cam_pred);
    rep.correction_deg = core::rotationDistanceRad(T_world_cam, T_world_cam_pred) / kDeg;
    rep.edge_inlier_ratio = stats.final_inlier_ratio;
    rep.edge_points = stats.edge_points;
    // The gate: max_correction_*, or three predicted sigmas when the prediction is less certain than that
    // (after a global initialisation, or after misses): a correction the prediction allows is not an outlier.
    rep.map_update = success && rep.correction_m <= std::max(options_.max_correction_m, 3 * rep.prior_sigma_m) &&
                     rep.correction_deg <= std::max(options_.max_correction_deg, 3 * rep.prior_sigma_deg);
    misses_ = rep.map_update ? 0 : misses_ + 1;
    if (!rep.map_update)
    {
        a.model.reset();
        return a;
    }
    if (f.map_lines || f.map_points || f.map_planes) a.T_world_cam = T_world_cam;
    // The edge residuals themselves in the window, linearised from the alignment's pose.
    estimation::DirectEdgeTerm d;
    d.field = &field;
    d.model = a.model.get();
    d.camera = &stereo_.left.model;
    d.sigma_px = f.direct_factor_sigma_px;
    d.effective_points = f.direct_factor_effective_points;
    d.truncation_px = refinement_.direct.truncation_px;
    d.huber_px = refinement_.direct.huber_px;
    in.direct_terms.push_back(d);
    a.T_map_body = T_world_cam * T_body_cam_.inverse();
    // The map side of the line factors needs only the quasi-image.
    if (f.map_lines) a.map_lines = quasiImageLines(rep);
    return a;
}

std::vector<MapLine> Tracker::quasiImageLines(FrameReport& rep) const
{
    mrpt::system::CTicTac tic;
    // Lines of the quasi-image rendered at the prediction, lifted at its pose.
    std::vector<MapLine> lines = line_extractor_->mapLines(quasi_.depth, core::toIsometry(quasi_.T_world_cam));
    rep.map_lines = int(lines.size());
    rep.ms_lines = tic.Tac() * 1e3;
    return lines;
}

MapLineOptions Tracker::mapLineOptions() const
{
    MapLineOptions lo;
    lo.max_angle_deg = options_.factors.line_max_angle_deg;
    lo.max_candidates = options_.factors.line_max_candidates;
    return lo;
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

void Tracker::addMapPoints(const dataset::StereoFrame& frame, const frontend::FrameFeatures& camera,
                           const Eigen::Isometry3d& T_world_cam, estimation::WindowInput& in, FrameReport& rep)
{
    mrpt::system::CTicTac tic;
    if (options_.factors.map_point_descriptor == MapPointDescriptor::OrientationField)
    {
        // Across the modality gap by structure, each observation with its candidate map points, reweighted as
        // structural factors (crossmodal_points.h).
        const CrossModalPointOptions& po = options_.factors.point_field;
        CrossModalPointStats stats;
        const auto associations = associateCrossModalPoints(describeCameraForMapPoints(grayImage(frame.left), po),
                                                            quasi_, map_, stereo_.left.model, T_world_cam,
                                                            rep.prior_sigma_m, rep.prior_sigma_deg * kDeg, po, &stats);
        appendAxisLineFactors(associations, options_.factors.point_sigma_px, in.lines);
        rep.quasi_keypoints = stats.map_keypoints;
        rep.point_factors = int(associations.size());
        size_t candidates = 0;
        for (const auto& a : associations) candidates += a.p_map.size();
        rep.point_candidates = associations.empty() ? 0 : double(candidates) / double(associations.size());
        if (frame.T_world_cam0)
            rep.point_correct = countCorrect(associations, stereo_.left.model, core::toIsometry(*frame.T_world_cam0));
        rep.ms_points = tic.Tac() * 1e3;
        return;
    }
    // The quasi-image's 8-bit image its features are extracted on: its gray image, or its reflectivity matched to
    // the camera image's histogram.
    cv::Mat quasi_gray = quasi_.gray;
    if (refinement_.quasi_gray == estimation::QuasiGray::MatchedReflectivity)
        quasi_gray = quasi::reflectivityMatchedToImage(quasi_, grayImage(frame.left));
    frontend::FrameFeatures fq;
    quasi_frontend_->extractPoints(quasi_gray, quasi_.valid, fq);
    MapPointOptions po;
    po.window_px = options_.factors.point_window_px;
    po.sigma_px = options_.factors.point_sigma_px;
    po.lift_radius_px = refinement_.lift_radius_px;
    in.points = associateMapPoints(camera.points, fq.points, quasi_, map_, stereo_.left.model, T_world_cam,
                                   frontend_options_.point_matching, po);
    rep.quasi_keypoints = int(fq.points.keypoints.size());
    rep.point_factors = int(in.points.size());
    rep.point_candidates = in.points.empty() ? 0 : 1;
    if (frame.T_world_cam0)
        rep.point_correct = countCorrectMatches(in.points, stereo_.left.model, core::toIsometry(*frame.T_world_cam0));
    rep.ms_points = tic.Tac() * 1e3;
}

void Tracker::addMapPlanes(const FrameMeasurement& m, const Eigen::Isometry3d& T_world_cam, estimation::WindowInput& in,
                           FrameReport& rep) const
{
    mrpt::system::CTicTac tic;
    std::vector<Eigen::Vector3d> p_cam;
    std::vector<double> sigma;
    mapPointsWithSigma(m, p_cam, sigma);
    // All points together count as plane_effective_points independent observations (neighbouring points share the
    // map's and the stereo's errors), as in the stereo map factor.
    const double scale = std::sqrt(std::max(1.0, double(p_cam.size()) / options_.factors.plane_effective_points));
    for (double& s : sigma) s *= scale;
    in.planes = plane_associator_->associate(p_cam, sigma, quasi_, T_world_cam);
    rep.plane_factors = int(in.planes.size());
    size_t candidates = 0;
    for (const auto& f : in.planes) candidates += f.candidates.size();
    rep.plane_candidates = in.planes.empty() ? 0 : double(candidates) / double(in.planes.size());
    rep.ms_planes = tic.Tac() * 1e3;
}

void Tracker::mapPointsWithSigma(const FrameMeasurement& m, std::vector<Eigen::Vector3d>& p_cam,
                                 std::vector<double>& sigma_m) const
{
    const double fb = stereo_.left.model.fx * stereo_.T_left_right.translation().norm();
    for (const frontend::StereoPoint& s : m.stereo)
    {
        const double z = s.p_left.z();
        if (z < 0.2 || z > options_.factors.stereo_map_max_depth_m || !s.p_left.allFinite()) continue;
        const double depth_sigma = z * z / fb * options_.factors.stereo_disparity_sigma_px;
        p_cam.push_back(s.p_left);
        sigma_m.push_back(std::hypot(options_.factors.stereo_map_sigma_m, depth_sigma));
    }
}

void Tracker::stereoMapPoints(const FrameMeasurement& m, std::vector<Eigen::Vector3d>& p_cam,
                              std::vector<double>& sigma_m) const
{
    if (!measurer_.denseStereo()) return mapPointsWithSigma(m, p_cam, sigma_m);
    for (const Eigen::Vector3f& p : m.dense)
    {
        if (p.z() > options_.factors.stereo_map_max_depth_m) continue;
        p_cam.push_back(p.cast<double>());
        sigma_m.push_back(std::hypot(options_.factors.stereo_map_sigma_m, measurer_.stereoCloud()->depthSigma(p.z())));
    }
}

void Tracker::addStereoMapTerm(const FrameMeasurement& m, estimation::WindowInput& in) const
{
    const MapFactorOptions& f = options_.factors;
    std::vector<Eigen::Vector3d> p_cam;
    std::vector<double> sigma_m;
    stereoMapPoints(m, p_cam, sigma_m);
    if (p_cam.size() < 10) return;
    const Eigen::Isometry3d T_world_cam = in.current.T_map_body * T_body_cam_;  // the prediction
    for (estimation::MapDistanceTerm& term : stereoMapTermsByTruncation(
             p_cam, sigma_m, f.stereo_map_truncation_m, f.stereo_map_truncation_sigmas, f.stereo_map_effective_points))
    {
        term.field = distance_field_;
        // The truncation keeps the whole sigma (how far off a point may be found); the weight its share across the
        // surface.
        if (f.stereo_map_sigma_along_normal)
            for (size_t i = 0; i < term.p_cam.size(); ++i)
                term.sigma_m[i] = sigmaAlongNormal(*distance_field_, T_world_cam, term.p_cam[i], term.sigma_m[i],
                                                   f.stereo_map_sigma_m);
        in.map_distance_terms.push_back(std::move(term));
    }
}

bool Tracker::gateStereo(const FrameMeasurement& m, const MapAlignment& a, const StereoGate& gate,
                         FrameReport& rep) const
{
    // The pose of an accepted map alignment (set with T_map_body): it rests on the left image alone.
    if (!a.T_map_body || !distance_field_ || !options_.temporal_landmarks) return true;
    const Eigen::Isometry3d T_world_cam_edges = *a.T_map_body * T_body_cam_;
    std::vector<Eigen::Vector3d> p_cam;
    std::vector<double> sigma_m;
    stereoMapPoints(m, p_cam, sigma_m);
    if (p_cam.size() < 10) return true;
    // The median, not the mean: clutter that the map lacks (people, moved objects) is far from every surface.
    std::vector<double> sigmas(p_cam.size());
    for (size_t i = 0; i < p_cam.size(); ++i)
        sigmas[i] = distance_field_->distance((T_world_cam_edges * p_cam[i]).cast<float>()) / sigma_m[i];
    std::nth_element(sigmas.begin(), sigmas.begin() + long(sigmas.size() / 2), sigmas.end());
    rep.stereo_map_sigmas = sigmas[sigmas.size() / 2];
    rep.stereo_rejected = gate.rejects(rep.stereo_map_sigmas, rep.edge_inlier_ratio);
    return !rep.stereo_rejected;
}

void Tracker::addVisualTerms(const dataset::StereoFrame& frame, const std::shared_ptr<const FrameMeasurement>& m,
                             const MapAlignment& a, bool stereo_ok, bool map_terms, estimation::WindowInput& in,
                             FrameReport& rep)
{
    const MapFactorOptions& f = options_.factors;
    const bool points = options_.temporal_landmarks;
    if (f.edge_trust_sigmas > 0 && a.T_map_body && !in.direct_terms.empty() && distance_field_)
    {  // the keyframe's quasi-image was rendered at the prediction
        StereoSurface stereo;
        stereoMapPoints(*m, stereo.p_cam, stereo.sigma_m);
        stereo.truncation_m = f.stereo_map_truncation_m;
        stereo.effective_points = f.stereo_map_effective_points;
        weighEdgeTerm(*distance_field_, core::toIsometry(quasi_.T_world_cam), *a.T_map_body * T_body_cam_, stereo,
                      f.edge_trust_sigmas, in.direct_terms);
    }
    if (a.T_world_cam && f.map_planes && points && stereo_ok) addMapPlanes(*m, *a.T_world_cam, in, rep);
    if (a.T_world_cam && f.map_lines)
        addMapLines(m->lines, a.map_lines, *a.T_world_cam, rep.prior_sigma_m, rep.prior_sigma_deg * kDeg, in, rep);
    // After the lines: with the orientation field the point associations are appended to in.lines.
    if (a.T_world_cam && f.map_points && points) addMapPoints(frame, m->left, *a.T_world_cam, in, rep);
    if (points && map_terms && options_.map_updates && f.stereo_map_factor && distance_field_ && stereo_ok)
        addStereoMapTerm(*m, in);
    rep.stereo_map_points = 0;
    for (const estimation::MapDistanceTerm& term : in.map_distance_terms)
        rep.stereo_map_points += int(term.p_cam.size());
    // A frame whose stereo was left out is not the next frame's landmarks either: they start again from the next
    // good frame.
    if (points && stereo_ok)
        temporalLandmarks(m, rep.t, in.landmarks);
    else if (!stereo_ok)
        previous_.reset();
    rep.landmarks = int(in.landmarks.size());
}

}  // namespace quasiloc::tracking
