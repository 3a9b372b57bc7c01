// Frame-to-frame stereo odometry (stereo_odometry.h): ORB stereo points of the previous frame, matched into this
// frame's left image near their predicted pixels, PnP with RANSAC, checked against the gyroscope.
#include <quasiloc/reloc/stereo_odometry.h>

#include <chrono>
#include <cmath>
#include <quasiloc/core/pose.h>
#include <quasiloc/frontend/point_matcher.h>

namespace quasiloc::reloc
{
namespace
{
frontend::FeatureOptions orbOptions(const StereoOdometryOptions& o)
{
    frontend::FeatureOptions f;
    f.type = frontend::FeatureType::Orb;
    f.max_keypoints = o.max_keypoints;
    f.dense_map = false;
    return f;
}

frontend::StereoOptions stereoOptions(const StereoOdometryOptions& o)
{
    frontend::StereoOptions s;
    s.max_depth_m = o.max_depth_m;
    return s;
}

double angleDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b)
{
    return Eigen::AngleAxisd(a.transpose() * b).angle() * 180 / M_PI;
}
}  // namespace

StereoOdometry::StereoOdometry(const core::StereoRig& rig, const StereoOdometryOptions& options)
    : rig_(rig),
      options_(options),
      extractor_(frontend::createFeatureExtractor(orbOptions(options))),
      stereo_(rig, stereoOptions(options))
{}

StereoOdometry::~StereoOdometry() = default;

OdometryStep StereoOdometry::track(const cv::Mat& left_raw, const cv::Mat& right_raw,
                                   const std::optional<Eigen::Matrix3d>& R_prev_cur)
{
    const auto t0 = std::chrono::steady_clock::now();
    auto cur = std::make_unique<Frame>();
    frontend::Features right;
    extractor_->extract(left_raw, cv::Mat(), cur->left);
    extractor_->extract(right_raw, cv::Mat(), right);
    for (const frontend::StereoPoint& s : stereo_.match(cur->left, right))
    {
        cur->stereo_left.push_back(s.left);
        cur->stereo_p.push_back(s.p_left);
    }
    OdometryStep step;
    step.stereo_points = int(cur->stereo_p.size());
    std::unique_ptr<Frame> prev = std::move(previous_);
    previous_ = std::move(cur);
    const Frame& now = *previous_;
    auto finish = [&](const std::string& reason) {
        step.reason = reason;
        step.ok = reason.empty();
        step.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        return step;
    };
    if (!prev) return finish("no previous frame");

    // The previous frame's stereo points as queries, searched near their predicted pixel in this left image.
    frontend::Features query;
    query.type = prev->left.type;
    query.descriptors =
        cv::Mat(int(prev->stereo_left.size()), prev->left.descriptors.cols, prev->left.descriptors.type());
    frontend::SearchRegion region;
    region.radius_px = options_.window_px;
    for (size_t i = 0; i < prev->stereo_left.size(); ++i)
    {
        const cv::KeyPoint& kp = prev->left.keypoints[size_t(prev->stereo_left[i])];
        query.keypoints.push_back(kp);
        prev->left.descriptors.row(prev->stereo_left[i]).copyTo(query.descriptors.row(int(i)));
        cv::Point2f centre = kp.pt;
        Eigen::Vector2d px;
        if (R_prev_cur && rig_.left.project(R_prev_cur->transpose() * prev->stereo_p[i].normalized(), px))
            centre = cv::Point2f(float(px.x()), float(px.y()));  // rotation only: the translation is small
        region.centers.push_back(centre);
    }
    frontend::PointMatchingOptions pm;
    pm.ratio = options_.ratio;
    pm.max_distance_hamming = options_.max_distance_hamming;
    const std::vector<frontend::PointMatch> matches = query.keypoints.empty()
                                                          ? std::vector<frontend::PointMatch>{}
                                                          : frontend::matchPoints(query, now.left, pm, &region);
    step.matches = int(matches.size());
    if (step.matches < options_.min_inliers)
        return finish("too few matches to the previous frame (" + std::to_string(step.matches) + ")");

    std::vector<Eigen::Vector2d> points2D;
    std::vector<Eigen::Vector3d> points3D;
    for (const auto& m : matches)
    {
        const cv::Point2f& pt = now.left.keypoints[size_t(m.train)].pt;
        points2D.emplace_back(pt.x, pt.y);
        points3D.push_back(prev->stereo_p[size_t(m.query)]);
    }
    estimation::AbsolutePoseOptions po;
    po.method = estimation::PnpMethod::Ransac;
    po.max_reproj_error_px = options_.max_reproj_error_px;
    po.min_inliers = options_.min_inliers;
    Eigen::Isometry3d T_cur_prev = Eigen::Isometry3d::Identity();
    estimation::AbsolutePoseStats stats;
    const bool found = estimation::estimateAbsolutePose(po, points2D, points3D, rig_.left, &T_cur_prev, &stats);
    step.inliers = stats.num_inliers;
    if (!found || step.inliers < options_.min_inliers)
        return finish("too few PnP inliers (" + std::to_string(step.inliers) + " < min_inliers " +
                      std::to_string(options_.min_inliers) + ")");
    step.T_prev_cur = T_cur_prev.inverse();
    if (R_prev_cur)
    {
        step.gyro_disagreement_deg = angleDeg(step.T_prev_cur.linear(), *R_prev_cur);
        if (step.gyro_disagreement_deg > options_.max_gyro_disagreement_deg)
            return finish("the rotation disagrees with the gyroscope's by " +
                          std::to_string(step.gyro_disagreement_deg) + " deg");
    }
    return finish("");
}

Eigen::Matrix3d gyroRotation(const std::vector<double>& t, const std::vector<Eigen::Vector3d>& gyro, double t_prev,
                             double t_cur, const Eigen::Matrix3d& R_cam_body)
{
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // body at t_cur in body at t_prev
    double from = t_prev;
    for (size_t i = 0; i < t.size() && i < gyro.size(); ++i)
    {
        if (t[i] <= t_prev || t[i] > t_cur) continue;
        const double dt = t[i] - from;
        const bool last = i + 1 == t.size() || t[i + 1] > t_cur;
        const double hold = dt + (last ? t_cur - t[i] : 0.0);
        const Eigen::Vector3d w = gyro[i] * hold;
        if (w.norm() > 0) R = R * Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
        from = t[i];
    }
    return R_cam_body * R * R_cam_body.transpose();
}

}  // namespace quasiloc::reloc
