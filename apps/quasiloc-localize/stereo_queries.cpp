#include "stereo_queries.h"

#include <chrono>
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <sstream>

namespace quasiloc::app
{
namespace
{
double secondsSince(std::chrono::steady_clock::time_point start)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/** The geometric answer in the rows the database modes fill: stage times as extract = stereo matching, retrieval =
 *  place retrieval, rerank = coarse search, pnp = refinement and polish; inliers = query points the map explains. */
reloc::LocalizationReport asReport(const reloc::GeometricLocalization& g, double ms_total)
{
    reloc::LocalizationReport r;
    r.localized = g.localized;
    r.reason = g.reason;
    r.T_world_cam = g.T_world_cam;
    r.inliers = int(std::lround(g.inlier_ratio * double(g.query_points)));
    r.correspondences = int(g.query_points);
    r.ms.extract = g.ms_cloud;
    r.ms.retrieval = g.ms_retrieval;
    r.ms.rerank = g.ms_search;
    r.ms.pnp = g.ms_refine;
    r.ms.total = ms_total;
    return r;
}
}  // namespace

StereoQueries::StereoQueries(const std::string& map_file, const core::StereoRig& rig,
                             const reloc::GeometricLocalizationOptions& options, QueryGravity gravity,
                             double gravity_window_s)
    : map_(map::LidarMap::load(map_file)), rig_(rig), gravity_(gravity), gravity_window_s_(gravity_window_s)
{
    const auto start = std::chrono::steady_clock::now();
    localizer_ = std::make_unique<reloc::GeometricLocalizer>(map_, rig_, options, map_file);
    localizer_->places();  // built now, so that no query's time holds them
    setup_s_ = secondsSince(start);
}

StereoQueries::~StereoQueries() = default;

void StereoQueries::observe(const dataset::StereoFrame& frame)
{
    if (gravity_ != QueryGravity::Imu) return;
    for (const auto& s : frame.imu) recent_imu_.push_back(s);
    while (!recent_imu_.empty() && recent_imu_.front().t < frame.timestamp - gravity_window_s_) recent_imu_.pop_front();
}

std::optional<Eigen::Vector3d> StereoQueries::upInCamera() const
{
    if (gravity_ == QueryGravity::Level) return Eigen::Vector3d(0, -1, 0);  // image y points down
    if (recent_imu_.empty()) return std::nullopt;
    std::vector<Eigen::Vector3d> acc;
    for (const auto& s : recent_imu_) acc.push_back(s.acc);
    return reloc::upInCamera(acc, core::toIsometry(rig_.T_body_left).linear().transpose());
}

QueryRow StereoQueries::localize(const dataset::StereoFrame& frame)
{
    QueryRow row;
    row.t = frame.timestamp;
    row.has_gt = bool(frame.T_world_cam0);
    const auto start = std::chrono::steady_clock::now();
    const auto up = upInCamera();
    if (up)
        last_ = localizer_->localize(frame.left, frame.right, *up);
    else
    {
        last_ = {};
        last_.reason = "no IMU sample within gravity_window_s before the frame (gravity = imu)";
    }
    row.report = asReport(last_, 1e3 * secondsSince(start));
    last_best_error_m_ = NAN;
    if (row.has_gt && up)
        last_best_error_m_ = core::translationDistance(core::fromIsometry(last_.T_world_cam), *frame.T_world_cam0);
    if (row.has_gt && row.report.localized)
    {
        const auto est = core::fromIsometry(row.report.T_world_cam);
        row.err_m = core::translationDistance(est, *frame.T_world_cam0);
        row.err_deg = core::rotationDistanceRad(est, *frame.T_world_cam0) * 180 / M_PI;
    }
    return row;
}

std::string StereoQueries::describeLast() const
{
    const reloc::GeometricLocalization& r = last_;
    std::ostringstream s;
    s << (r.localized ? "localized" : "not localized: " + r.reason);
    if (std::isfinite(last_best_error_m_)) s << "; best pose " << last_best_error_m_ << " m from the ground truth";
    s << "; query points " << r.query_points << ", inlier ratio " << r.inlier_ratio << ", candidates " << r.candidates;
    if (r.retrieved_places > 0) s << ", places retrieved " << r.retrieved_places;
    if (r.runner_up_inlier_ratio > 0)
        s << ", rival place " << r.runner_up_offset_m << " m / " << r.runner_up_offset_deg << " deg away explains "
          << r.runner_up_inlier_ratio;
    return s.str();
}

std::string StereoQueries::summary() const
{
    std::ostringstream s;
    s << map_.size() << " map points, " << localizer_->positions() << " candidate positions";
    if (const auto* places = localizer_->places())
        s << ", " << places->size() << " places (profiles " << localizer_->placesBuildSeconds() << " s)";
    s << "; set up in " << setup_s_ << " s";
    return s.str();
}

}  // namespace quasiloc::app
