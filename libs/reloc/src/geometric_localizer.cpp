// Global localization by geometry (geometric_localizer.h): coarse 4-DoF search, 6-DoF refinement, decision.
#include <opencv2/core/utility.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/estimation/pose_parametrization.h>
#include <quasiloc/reloc/geometric_localizer.h>

#include "near_points.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>

namespace quasiloc::reloc
{
namespace
{
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

struct Candidate
{
    Eigen::Isometry3d T_world_cam;
    double score = 0;  ///< coarse: mean truncated squared distance (lower is better); refined: inlier share
};

/** One damped Gauss-Newton step on T (right perturbation [dtheta; dp]) from the normal equations H, g (H is
 *  modified); false when the step is not finite or small enough to stop. */
bool gaussNewtonStep(Eigen::Matrix<double, 6, 6>& H, const Eigen::Matrix<double, 6, 1>& g, Eigen::Isometry3d& T)
{
    H.diagonal().array() += 1e-6 * (1.0 + H.diagonal().array());
    const estimation::Vector6d step = -H.ldlt().solve(g);
    if (!step.allFinite()) return false;
    T = estimation::boxPlus(T, step);
    return step.tail<3>().norm() >= 1e-4 || step.head<3>().norm() >= 1e-5;
}

/** The stereo options of the place profile's points: the localizer's, farther and more of them. */
StereoCloudOptions placeStereoOptions(const GeometricLocalizationOptions& o)
{
    StereoCloudOptions s = o.stereo;
    s.max_depth_m = std::max(o.place_query_depth_m, s.max_depth_m);
    s.max_points = std::max(s.max_points, 20000);
    return s;
}

double rotationDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b)
{
    return core::rotationDistanceRad(a, b) * 180.0 / M_PI;
}
}  // namespace

Eigen::Vector3d upInCamera(const std::vector<Eigen::Vector3d>& acc_body, const Eigen::Matrix3d& R_cam_body)
{
    core::require(!acc_body.empty(), "IMU", "no accelerometer sample for the gravity direction");
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& a : acc_body) mean += a;
    core::require(mean.norm() > 1e-6, "IMU", "zero mean specific force: no gravity direction");
    return (R_cam_body * mean).normalized();
}

std::shared_ptr<const map::DistanceField> GeometricLocalizer::buildField(const map::LidarMap& map,
                                                                         const GeometricLocalizationOptions& o,
                                                                         const std::string& input)
{
    o.check(input);
    map::DistanceFieldOptions f;
    f.voxel_m = o.field_voxel_m;
    f.max_distance_m = o.field_max_distance_m;
    f.layout = o.field_layout;
    f.margin_m = std::max(1.0, o.field_max_distance_m);
    f.memory_budget_mb = o.field_memory_budget_mb;
    f.focus_radius_m = o.field_focus_radius_m;
    f.tile_cache = o.field_tile_cache;
    return std::make_shared<const map::DistanceField>(map::DistanceField::build(map, f, input));
}

GeometricLocalizer::GeometricLocalizer(const map::LidarMap& map, const core::StereoRig& rig,
                                       const GeometricLocalizationOptions& o, const std::string& input)
    : GeometricLocalizer(map, rig, o, buildField(map, o, input),
                         std::make_shared<const map::VisibilityIndex>(map, map::VisibilityIndex::Options{}), input)
{}

GeometricLocalizer::GeometricLocalizer(const map::LidarMap& map, const core::StereoRig& rig,
                                       const GeometricLocalizationOptions& o,
                                       std::shared_ptr<const map::DistanceField> field,
                                       std::shared_ptr<const map::VisibilityIndex> index, const std::string& input)
    : options_(o),
      field_(std::move(field)),
      index_(std::move(index)),
      stereo_(rig, o.stereo),
      place_stereo_(rig, placeStereoOptions(o))
{
    core::require(index_ && index_->size() == map.size(), input, "the visibility index is not the map's");
    positions_ = reloc::candidatePositions(map, o, input);
    setUpPlaces(map, input);
}

std::vector<Eigen::Vector3d> candidatePositions(const map::LidarMap& map, const GeometricLocalizationOptions& o,
                                                const std::string& input)
{
    ViewSamplingOptions vs;
    vs.grid_spacing_m = o.grid_spacing_m;
    vs.heights_m = o.heights_m;
    vs.num_headings = 1;
    vs.pitches_deg = {0.0};
    vs.clearance_m = o.clearance_m;
    vs.require_enclosed = o.require_enclosed;
    vs.ceiling_min_share = o.ceiling_min_share;
    vs.region = o.region;
    std::vector<Eigen::Vector3d> positions;
    for (const auto& p : sampleViewpoints(map, vs)) positions.emplace_back(p.x(), p.y(), p.z());
    core::require(!positions.empty(), input, "no free camera position for global localization by geometry");
    return positions;
}

GeometricLocalizer::~GeometricLocalizer() = default;

GeometricLocalization GeometricLocalizer::localize(const cv::Mat& left_raw, const cv::Mat& right_raw,
                                                   const Eigen::Vector3d& up_cam, const SearchSphere* near,
                                                   std::vector<Eigen::Vector3f>* points_cam) const
{
    const auto t0 = Clock::now();
    auto [points, place_points] = queryClouds(left_raw, right_raw);
    const double ms_cloud = msSince(t0);
    GeometricLocalization r = localizePoints(points, up_cam, near, retrieval_ ? &place_points : nullptr);
    r.ms_cloud = ms_cloud;
    if (points_cam) *points_cam = std::move(points);
    return r;
}

std::pair<std::vector<Eigen::Vector3f>, std::vector<Eigen::Vector3f>> GeometricLocalizer::queryClouds(
    const cv::Mat& left_raw, const cv::Mat& right_raw) const
{
    if (!retrieval_) return {stereo_.compute(left_raw, right_raw), {}};
    // One matching for both clouds: the geometric check's and the place profile's (farther).
    const StereoDisparity d = stereo_.disparity(left_raw, right_raw);
    return {stereo_.points(d), place_stereo_.points(d)};
}

bool depthAwareInlier(const map::DistanceField& field, const Eigen::Vector3f& p_world, const Eigen::Vector3f& ray_world,
                      double inlier_m, double depth_tolerance_m, bool along_normal)
{
    if (!along_normal) return field.distance(p_world) < float(inlier_m + depth_tolerance_m);
    Eigen::Vector3f g;
    const float d = field.distance(p_world, g);
    const float n = g.norm(), r = ray_world.norm();
    // Where the field has no gradient (beyond its truncation, or between surfaces) the whole tolerance holds.
    const double share = n > 0.5f && r > 0 ? std::abs(g.dot(ray_world)) / (n * r) : 1.0;
    return d < float(inlier_m + depth_tolerance_m * share);
}

double GeometricLocalizer::inlierRatio(const std::vector<Eigen::Vector3f>& points_cam,
                                       const Eigen::Isometry3d& T_world_cam) const
{
    if (points_cam.empty()) return 0;
    const Eigen::Matrix3f R = T_world_cam.linear().cast<float>();
    const Eigen::Vector3f t = T_world_cam.translation().cast<float>();
    size_t in = 0;
    for (const auto& p : points_cam)
        in += depthAwareInlier(*field_, R * p + t, R * p, options_.inlier_m, 2 * stereo_.depthSigma(p.z()),
                               options_.check_depth_along_normal);
    return double(in) / double(points_cam.size());
}

double GeometricLocalizer::refine(const std::vector<Eigen::Vector3f>& points_cam, Eigen::Isometry3d& T_world_cam) const
{
    using Matrix6d = Eigen::Matrix<double, 6, 6>;
    using Vector6d = Eigen::Matrix<double, 6, 1>;
    const std::vector<double> weight = pointWeights(points_cam);
    for (double truncation : options_.refine_truncations_m)
        for (int it = 0; it < options_.refine_iterations; ++it)
        {
            // Residual: the distance of each point to the map; right perturbation T exp([dtheta; dp]):
            // d q / d dtheta = -R [p]x, d q / d dp = R.
            Matrix6d H = Matrix6d::Zero();
            Vector6d g = Vector6d::Zero();
            const Eigen::Matrix3d R = T_world_cam.linear();
            const Eigen::Matrix3f Rf = R.cast<float>();
            const Eigen::Vector3f tf = T_world_cam.translation().cast<float>();
            int used = 0;
            for (size_t i = 0; i < points_cam.size(); ++i)
            {
                const Eigen::Vector3f& p = points_cam[i];
                Eigen::Vector3f grad;
                const float d = field_->distance(Rf * p + tf, grad);
                if (d >= truncation) continue;  // truncated least squares: unexplained points do not pull
                const Eigen::Vector3d gw = grad.cast<double>();
                Vector6d J;
                J.head<3>() = -(gw.transpose() * R * estimation::hat(p.cast<double>())).transpose();
                J.tail<3>() = R.transpose() * gw;
                H += weight[i] * J * J.transpose();
                g += weight[i] * J * double(d);
                ++used;
            }
            if (used < 6 || !gaussNewtonStep(H, g, T_world_cam)) break;
        }
    return inlierRatio(points_cam, T_world_cam);
}

std::vector<double> GeometricLocalizer::pointWeights(const std::vector<Eigen::Vector3f>& points_cam) const
{
    // Each point weighs by its noise: the field's own (half a voxel) and the stereo depth's, which grows with the
    // depth squared (far points are many, since far surfaces are large, and each is a few centimetres off).
    std::vector<double> weight(points_cam.size());
    const double field_sigma = 0.5 * field_->voxelSize();
    for (size_t i = 0; i < points_cam.size(); ++i)
        weight[i] = field_sigma * field_sigma /
                    (field_sigma * field_sigma + std::pow(stereo_.depthSigma(points_cam[i].z()), 2));
    return weight;
}

void GeometricLocalizer::polish(const std::vector<Eigen::Vector3f>& points_cam, Eigen::Isometry3d& T_world_cam) const
{
    using Matrix6d = Eigen::Matrix<double, 6, 6>;
    using Vector6d = Eigen::Matrix<double, 6, 1>;
    if (options_.polish_truncations_m.empty() || points_cam.empty()) return;
    const std::vector<double> weight = pointWeights(points_cam);
    // The map points near the query, gathered once: exact while no query point moves more than the margin.
    const float max_truncation =
        float(*std::max_element(options_.polish_truncations_m.begin(), options_.polish_truncations_m.end()));
    constexpr float kMargin = 0.15f;
    std::vector<Eigen::Vector3f> gathered_at;
    std::unique_ptr<NearPoints> near;
    const auto gather = [&] {
        gathered_at.clear();
        for (const auto& p : points_cam) gathered_at.push_back((T_world_cam * p.cast<double>()).cast<float>());
        near = std::make_unique<NearPoints>(*index_, gathered_at, max_truncation + kMargin, max_truncation);
    };
    gather();
    for (double truncation : options_.polish_truncations_m)
        for (int it = 0; it < options_.refine_iterations; ++it)
        {
            // Residual: point minus its nearest map point (3-D); same right perturbation as refine().
            Matrix6d H = Matrix6d::Zero();
            Vector6d g = Vector6d::Zero();
            const Eigen::Matrix3d R = T_world_cam.linear();
            std::vector<Eigen::Vector3f> q_world(points_cam.size());
            float moved2 = 0;
            for (size_t i = 0; i < points_cam.size(); ++i)
            {
                q_world[i] = (T_world_cam * points_cam[i].cast<double>()).cast<float>();
                moved2 = std::max(moved2, (q_world[i] - gathered_at[i]).squaredNorm());
            }
            if (moved2 > kMargin * kMargin) gather();
            int used = 0;
            for (size_t i = 0; i < points_cam.size(); ++i)
            {
                Eigen::Vector3f m;
                float d2;
                if (!near->nearest(q_world[i], float(truncation), m, d2)) continue;
                const Eigen::Vector3d p = points_cam[i].cast<double>();
                const Eigen::Vector3d e = T_world_cam * p - m.cast<double>();
                Eigen::Matrix<double, 3, 6> J;
                J.leftCols<3>() = -R * estimation::hat(p);
                J.rightCols<3>() = R;
                H += weight[i] * J.transpose() * J;
                g += weight[i] * J.transpose() * e;
                ++used;
            }
            if (used < 6 || !gaussNewtonStep(H, g, T_world_cam)) break;
        }
}

namespace
{
/** Azimuth [rad] of the camera's viewing direction in the world's xy plane (of its x axis when it looks up or
 *  down). */
double azimuth(const Eigen::Matrix3d& R_world_cam)
{
    Eigen::Vector3d d = R_world_cam.col(2);
    if (std::hypot(d.x(), d.y()) < 0.3) d = R_world_cam.col(0);
    return std::atan2(d.y(), d.x());
}
}  // namespace

bool SearchSphere::headingAdmits(const Eigen::Matrix3d& R) const
{
    if (!R_world_cam) return true;
    const double diff = std::remainder(azimuth(R) - azimuth(*R_world_cam), 2 * M_PI);
    return std::abs(diff) * 180.0 / M_PI <= heading_bound_deg;
}

GeometricLocalization GeometricLocalizer::localizePoints(const std::vector<Eigen::Vector3f>& points_cam,
                                                         const Eigen::Vector3d& up_cam, const SearchSphere* near,
                                                         const std::vector<Eigen::Vector3f>* place_points) const
{
    GeometricLocalization r;
    r.query_points = points_cam.size();
    if (points_cam.size() < size_t(options_.score_points))
    {
        r.reason = "too few stereo points (" + std::to_string(points_cam.size()) + " < score_points " +
                   std::to_string(options_.score_points) + ")";
        return r;
    }
    std::vector<size_t> searched;  // indices into positions_
    for (size_t i = 0; i < positions_.size(); ++i)
        if (!near || (positions_[i] - near->centre).norm() <= near->radius_m) searched.push_back(i);
    if (searched.empty())
    {
        std::ostringstream why;
        why.precision(3);
        why << "no candidate position within " << near->radius_m << " m of (" << near->centre.transpose() << ")";
        r.reason = why.str();
        return r;
    }
    // Place retrieval on a large map: only the positions near the best places, at headings near theirs.
    std::vector<std::vector<bool>> yaws_near;
    if (retrieval_ && searched.size() > size_t(options_.retrieval_min_positions))
    {
        const auto tr = Clock::now();
        const std::vector<RetrievedPlace> retrieved = retrieve(place_points ? *place_points : points_cam, up_cam, near);
        if (retrieved.empty())
        {
            r.reason = "too few stereo points for place retrieval (they cover fewer than retrieval_min_sectors " +
                       std::to_string(options_.retrieval_min_sectors) + " profile cells)";
            r.ms_retrieval = msSince(tr);
            return r;
        }
        // Only the positions near a retrieved place stay searched (the sort below is over all of them).
        const std::vector<std::vector<bool>> all_yaws = retrievedYaws(searched, retrieved);
        std::vector<size_t> kept;
        for (size_t i = 0; i < searched.size(); ++i)
            if (std::find(all_yaws[i].begin(), all_yaws[i].end(), true) != all_yaws[i].end())
            {
                kept.push_back(searched[i]);
                yaws_near.push_back(all_yaws[i]);
            }
        searched = std::move(kept);
        r.retrieved_places = retrieved.size();
        r.ms_retrieval = msSince(tr);
    }
    // Coarse search: rotation R_world_cam = Rz(yaw) * R_level, where R_level turns the camera's up into world +z.
    auto t0 = Clock::now();
    const Eigen::Matrix3d R_level =
        Eigen::Quaterniond::FromTwoVectors(up_cam.normalized(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    std::vector<Eigen::Vector3f> scored;
    const double stride = double(points_cam.size()) / options_.score_points;
    for (int i = 0; i < options_.score_points; ++i) scored.push_back(points_cam[size_t(i * stride)]);
    const int yaws = options_.num_yaws;
    std::vector<Eigen::Matrix3f> rotations;
    std::vector<std::vector<Eigen::Vector3f>> rotated(static_cast<size_t>(yaws));
    std::vector<bool> yaw_searched(size_t(yaws), true);
    for (int k = 0; k < yaws; ++k)
    {
        const Eigen::Matrix3d R =
            Eigen::AngleAxisd(2 * M_PI * k / yaws, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R_level;
        rotations.push_back(R.cast<float>());
        if (near && near->R_world_cam)
        {  // half a yaw step of slack: the grid's nearest heading to an admitted one is searched
            SearchSphere wider = *near;
            wider.heading_bound_deg += 180.0 / yaws;
            yaw_searched[size_t(k)] = wider.headingAdmits(R);
        }
        if (yaw_searched[size_t(k)])
            for (const auto& p : scored) rotated[size_t(k)].push_back(R.cast<float>() * p);
    }
    const float trunc2 = float(options_.coarse_truncation_m * options_.coarse_truncation_m);
    std::vector<float> scores(searched.size() * size_t(yaws));
    cv::parallel_for_(cv::Range(0, int(searched.size())), [&](const cv::Range& range) {
        for (int i = range.start; i < range.end; ++i)
        {
            const Eigen::Vector3f t = positions_[searched[size_t(i)]].cast<float>();
            for (int k = 0; k < yaws; ++k)
            {
                if (!yaw_searched[size_t(k)] || (!yaws_near.empty() && !yaws_near[size_t(i)][size_t(k)]))
                {
                    scores[size_t(i) * size_t(yaws) + size_t(k)] = std::numeric_limits<float>::infinity();
                    continue;
                }
                float sum = 0;
                for (const auto& p : rotated[size_t(k)])
                {
                    const float d = field_->distance(p + t);
                    sum += std::min(d * d, trunc2);
                }
                scores[size_t(i) * size_t(yaws) + size_t(k)] = sum / float(scored.size());
            }
        }
    });
    r.candidates = size_t(std::count_if(scores.begin(), scores.end(), [](float v) { return std::isfinite(v); }));
    std::vector<size_t> order(scores.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return scores[a] < scores[b] || (scores[a] == scores[b] && a < b); });
    // Distinct starting candidates: > 0.5 m or > 20 deg of heading from every one already taken.
    std::vector<Candidate> starts;
    for (size_t idx : order)
    {
        if (int(starts.size()) >= options_.refine_candidates || !std::isfinite(scores[idx])) break;
        Candidate c;
        c.T_world_cam.setIdentity();
        c.T_world_cam.linear() = rotations[idx % size_t(yaws)].cast<double>();
        c.T_world_cam.translation() = positions_[searched[idx / size_t(yaws)]];
        const bool near_taken = std::any_of(starts.begin(), starts.end(), [&](const Candidate& s) {
            return core::translationDistance(s.T_world_cam, c.T_world_cam) < 0.5 &&
                   rotationDeg(s.T_world_cam, c.T_world_cam) < 20;
        });
        if (!near_taken) starts.push_back(c);
    }
    r.ms_search = msSince(t0);

    t0 = Clock::now();
    std::vector<Candidate> refined(starts.size());
    cv::parallel_for_(cv::Range(0, int(starts.size())), [&](const cv::Range& range) {
        for (int i = range.start; i < range.end; ++i)
        {
            refined[size_t(i)] = starts[size_t(i)];
            refined[size_t(i)].score = refine(points_cam, refined[size_t(i)].T_world_cam);
        }
    });
    r.ms_refine = msSince(t0);
    if (near)  // refinement may have turned a candidate out of the heading's bound
        refined.erase(std::remove_if(refined.begin(), refined.end(),
                                     [&](const Candidate& c) { return !near->headingAdmits(c.T_world_cam.linear()); }),
                      refined.end());
    if (refined.empty())
    {
        r.reason = "no refined pose within the heading bound (" + std::to_string(near->heading_bound_deg) + " deg)";
        return r;
    }
    std::stable_sort(refined.begin(), refined.end(),
                     [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
    const Candidate& best = refined.front();
    r.T_world_cam = best.T_world_cam;
    if (!options_.polish_truncations_m.empty())
    {
        const auto t1 = Clock::now();
        polish(points_cam, r.T_world_cam);
        r.ms_refine += msSince(t1);
    }
    r.inlier_ratio = inlierRatio(points_cam, r.T_world_cam);
    // Other places: refined poses farther than 0.3 m or 5 deg from the best (the first is the runner-up).
    for (const Candidate& c : refined)
    {
        const double offset_m = core::translationDistance(c.T_world_cam, best.T_world_cam);
        const double offset_deg = rotationDeg(c.T_world_cam, best.T_world_cam);
        if (offset_m <= 0.3 && offset_deg <= 5) continue;
        if (r.runner_up_inlier_ratio == 0)
        {
            r.runner_up_inlier_ratio = c.score;
            r.runner_up_offset_m = offset_m;
            r.runner_up_offset_deg = offset_deg;
        }
        if (c.score >= options_.ambiguity_ratio * r.inlier_ratio) r.alternatives.push_back(c.T_world_cam);
    }
    std::ostringstream why;
    why.precision(3);
    if (r.inlier_ratio < options_.min_inlier_ratio)
        why << "best pose explains " << 100 * r.inlier_ratio << " % of the stereo points (< min_inlier_ratio "
            << 100 * options_.min_inlier_ratio << " %)";
    else if (r.runner_up_inlier_ratio >= options_.ambiguity_ratio * r.inlier_ratio)
    {
        why << "ambiguous: another place explains " << 100 * r.runner_up_inlier_ratio << " % against "
            << 100 * r.inlier_ratio << " %";
        r.ambiguous = true;
    }
    r.reason = why.str();
    r.localized = r.reason.empty();
    return r;
}

}  // namespace quasiloc::reloc
