#include "stereo_queries.h"

#include <chrono>
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <sstream>
#include <tuple>

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
                             double gravity_window_s, const StereoSpanSettings& span)
    : map_(map::LidarMap::load(map_file)),
      rig_(rig),
      gravity_(gravity),
      gravity_window_s_(gravity_window_s),
      span_settings_(span),
      span_voxel_m_(options.stereo.voxel_m)
{
    const auto start = std::chrono::steady_clock::now();
    localizer_ = std::make_unique<reloc::GeometricLocalizer>(map_, rig_, options, map_file);
    localizer_->places();  // built now, so that no query's time holds them
    if (span_settings_.frames > 1)
    {
        odometry_ = std::make_unique<reloc::StereoOdometry>(rig_);
        span_ = std::make_unique<reloc::StereoSpan>(span_settings_.frames);
    }
    setup_s_ = secondsSince(start);
}

StereoQueries::~StereoQueries() = default;

void StereoQueries::observe(const dataset::StereoFrame& frame, size_t frames_to_query)
{
    if (span_ && frames_to_query < size_t(span_settings_.frames)) addToSpan(frame, frames_to_query);
    if (gravity_ != QueryGravity::Imu) return;
    for (const auto& s : frame.imu) recent_imu_.push_back(s);
    while (!recent_imu_.empty() && recent_imu_.front().t < frame.timestamp - gravity_window_s_) recent_imu_.pop_front();
}

void StereoQueries::addToSpan(const dataset::StereoFrame& frame, size_t frames_to_query)
{
    const auto start = std::chrono::steady_clock::now();
    const bool consecutive = last_span_index_ && *last_span_index_ + 1 == frame.index;
    if (!consecutive)
    {
        odometry_->reset();
        span_->clear();
        span_truth_.clear();
    }
    // The gyroscope's rotation since the previous frame: the odometry's search prior and check.
    std::optional<Eigen::Matrix3d> R_prev_cur;
    if (consecutive && !frame.imu.empty())
    {
        std::vector<double> t;
        std::vector<Eigen::Vector3d> gyro;
        for (const auto& s : frame.imu)
        {
            t.push_back(s.t);
            gyro.push_back(s.gyro);
        }
        const Eigen::Matrix3d R_cam_body = core::toIsometry(rig_.T_body_left).linear().transpose();
        R_prev_cur = reloc::gyroRotation(t, gyro, last_span_t_, frame.timestamp, R_cam_body);
    }
    const reloc::OdometryStep step = odometry_->track(frame.left, frame.right, R_prev_cur);
    if (consecutive)
    {
        ++span_steps_;
        span_refused_ += !step.ok;
        if (!step.ok) last_refusal_ = step.reason;
    }
    reloc::SpanFrame f;
    f.t = frame.timestamp;
    f.linked = step.ok;
    f.T_prev_this = step.T_prev_cur;
    f.has_clouds = frames_to_query % size_t(span_settings_.cloud_step) == 0;
    if (f.has_clouds) std::tie(f.points, f.place_points) = localizer_->queryClouds(frame.left, frame.right);
    span_->add(std::move(f));
    span_truth_.emplace_back(frame.timestamp, frame.T_world_cam0);
    while (span_truth_.size() > span_->size()) span_truth_.pop_front();
    last_span_index_ = frame.index;
    last_span_t_ = frame.timestamp;
    span_work_ms_ += 1e3 * secondsSince(start);
}

reloc::GeometricLocalization StereoQueries::localizeSpan(const dataset::StereoFrame& frame, const Eigen::Vector3d& up)
{
    reloc::GeometricLocalization r;
    if (span_->size() == 0 || span_->newest().t != frame.timestamp)
    {
        r.reason = "the queried frame was not observed before it was localized";
        return r;
    }
    const auto start = std::chrono::steady_clock::now();
    const reloc::JoinedClouds j = span_->join(span_voxel_m_, size_t(span_settings_.max_points), 0);
    const double ms_join = 1e3 * secondsSince(start);
    r = localizer_->localizePoints(j.points, up, nullptr, j.place_points.empty() ? nullptr : &j.place_points);
    r.ms_cloud = span_work_ms_ + ms_join;
    last_span_work_ms_ = span_work_ms_;
    std::ostringstream s;
    s.precision(3);
    s << "; span: " << j.frames << " clouds of " << j.linked_frames << " linked frames over " << j.span_s << " s, "
      << j.path_m << " m of path, " << span_refused_ << " of " << span_steps_ << " odometry steps refused";
    if (span_refused_ > 0) s << " (the last: " << last_refusal_ << ")";
    // The odometry's error over the span: the oldest joined frame's pose in the newest, against the ground truth's.
    const auto& newest = span_truth_.back().second;
    for (const auto& [t, truth] : span_truth_)
        if (t == j.oldest_t && truth && newest && j.frames > 1)
        {
            const auto T_true = core::toIsometry(*newest).inverse() * core::toIsometry(*truth);
            s << ", odometry error over the span " << (T_true.translation() - j.T_newest_oldest.translation()).norm()
              << " m / "
              << core::rotationDistanceRad(core::fromIsometry(T_true), core::fromIsometry(j.T_newest_oldest)) * 180 /
                     M_PI
              << " deg";
        }
    last_span_ = s.str();
    span_work_ms_ = 0;
    span_steps_ = span_refused_ = 0;
    last_refusal_.clear();
    return r;
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
    last_span_.clear();
    last_span_work_ms_ = 0;
    if (up && span_)
        last_ = localizeSpan(frame, *up);
    else if (up)
        last_ = localizer_->localize(frame.left, frame.right, *up);
    else
    {
        last_ = {};
        last_.reason = "no IMU sample within gravity_window_s before the frame (gravity = imu)";
    }
    // A span's odometry and clouds were computed as its frames came: they count in the query's time.
    row.report = asReport(last_, 1e3 * secondsSince(start) + last_span_work_ms_);
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
    s << last_span_;
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
