#include <algorithm>
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/tracking/along_track_search.h>

namespace quasiloc::tracking
{
Eigen::Vector3d horizontalViewingDirection(const Eigen::Isometry3d& T_world_cam)
{
    Eigen::Vector3d d = T_world_cam.linear().col(2);
    d.z() = 0;
    const double n = d.norm();
    return n > 1e-6 ? Eigen::Vector3d(d / n) : Eigen::Vector3d::Zero();
}

AlongTrackFix searchAlongTrack(const map::DistanceField& field, const Eigen::Isometry3d& T_world_cam,
                               const std::vector<Eigen::Vector3d>& p_cam, const std::vector<double>& sigma_m,
                               const AlongTrackSearchOptions& o)
{
    core::require(p_cam.size() == sigma_m.size(), "searchAlongTrack", "needs one sigma per point");
    core::require(o.range_m > 0 && o.step_m > 0 && o.step_m <= o.range_m && o.cap_sigmas > 0 &&
                      o.effective_points > 0 && o.min_gain >= 0 && o.unique_m > 0 && o.smooth_m >= 0,
                  "searchAlongTrack", "options out of range");
    AlongTrackFix fix;
    fix.direction_world = horizontalViewingDirection(T_world_cam);
    if (p_cam.empty() || fix.direction_world.isZero()) return fix;
    const int half = int(std::floor(o.range_m / o.step_m + 1e-9));
    std::vector<Eigen::Vector3f> p_world(p_cam.size());
    std::vector<float> inv_sigma(p_cam.size());
    for (size_t i = 0; i < p_cam.size(); ++i)
    {
        core::require(sigma_m[i] > 0, "searchAlongTrack", "a point's sigma is <= 0");
        p_world[i] = (T_world_cam * p_cam[i]).cast<float>();
        inv_sigma[i] = float(1.0 / sigma_m[i]);
    }
    // Each point's share of the chi-square: the n points count as effective_points observations.
    const double scale = std::min(1.0, o.effective_points / double(p_cam.size()));
    const float cap2 = float(o.cap_sigmas * o.cap_sigmas);
    std::vector<double> chi2(size_t(2 * half + 1));
    for (int k = -half; k <= half; ++k)
    {
        const Eigen::Vector3f shift = (float(k * o.step_m) * fix.direction_world).cast<float>();
        double sum = 0;
        for (size_t i = 0; i < p_world.size(); ++i)
        {
            const float r = field.distance(p_world[i] + shift) * inv_sigma[i];
            sum += std::min(r * r, cap2);
        }
        chi2[size_t(k + half)] = scale * sum;
    }
    // The score of one shift is noisy (the points are a sample of the surfaces): the minimum of many such scores lies
    // below the prediction's by chance. Each shift is scored by the mean over its neighbours within smooth_m.
    const int smooth = int(std::lround(o.smooth_m / o.step_m));
    if (smooth > 0)
    {
        const std::vector<double> raw = chi2;
        for (int k = 0; k < int(raw.size()); ++k)
        {
            double sum = 0;
            int n = 0;
            for (int j = std::max(0, k - smooth); j <= std::min(int(raw.size()) - 1, k + smooth); ++j, ++n)
                sum += raw[size_t(j)];
            chi2[size_t(k)] = sum / n;
        }
    }
    const size_t best = size_t(std::min_element(chi2.begin(), chi2.end()) - chi2.begin());
    const int k_best = int(best) - half;
    const int unique_steps = int(std::ceil(o.unique_m / o.step_m - 1e-9));
    double runner_up = INFINITY;
    for (int k = -half; k <= half; ++k)
        if (std::abs(k - k_best) >= unique_steps) runner_up = std::min(runner_up, chi2[size_t(k + half)]);
    fix.shift_m = k_best * o.step_m;
    fix.chi2_prediction = chi2[size_t(half)];
    fix.chi2_best = chi2[best];
    fix.chi2_runner_up = runner_up;
    fix.found =
        k_best != 0 && fix.chi2_prediction - fix.chi2_best >= o.min_gain && runner_up - fix.chi2_best >= o.min_gain;
    return fix;
}

estimation::PoseMeasurement alongTrackMeasurement(const AlongTrackFix& fix, const Eigen::Isometry3d& T_map_body_pred,
                                                  double sigma_m)
{
    core::require(fix.found && sigma_m > 0, "alongTrackMeasurement", "needs a fix and a sigma > 0");
    estimation::PoseMeasurement m;
    m.T_map_body = T_map_body_pred;
    m.T_map_body.translation() += fix.shift_m * fix.direction_world;
    // The tangent's translation is in the body frame (pose_parametrization.h).
    const Eigen::Vector3d u = T_map_body_pred.linear().transpose() * fix.direction_world;
    m.information.setZero();
    m.information.bottomRightCorner<3, 3>() = u * u.transpose() / (sigma_m * sigma_m);
    return m;
}

void widenAlongTrack(estimation::StatePrior& prior, const AlongTrackFix& fix, double velocity_sigma)
{
    if (!fix.found) return;
    constexpr int kPosition = 3, kVelocity = 6;
    const estimation::Matrix15d identity = estimation::Matrix15d::Identity();
    estimation::Matrix15d covariance = prior.information.ldlt().solve(identity);
    const Eigen::Vector3d u = prior.mean.T_map_body.linear().transpose() * fix.direction_world;
    covariance.block<3, 3>(kPosition, kPosition) += fix.shift_m * fix.shift_m * u * u.transpose();
    covariance.block<3, 3>(kVelocity, kVelocity) +=
        velocity_sigma * velocity_sigma * fix.direction_world * fix.direction_world.transpose();
    const estimation::Matrix15d widened = covariance.ldlt().solve(identity);
    prior.information = 0.5 * (widened + widened.transpose());
}

AlongTrackFix correctAlongTrack(const map::DistanceField& field, const MapFactorOptions& options,
                                const Eigen::Isometry3d& T_body_cam, const std::vector<Eigen::Vector3d>& p_cam,
                                const std::vector<double>& sigma_m, estimation::FrameState& previous,
                                estimation::StatePrior& prior, estimation::FrameState& start,
                                std::vector<estimation::PoseMeasurement>& measurements)
{
    AlongTrackSearchOptions o;
    o.range_m = options.along_track_range_m;
    o.step_m = std::min(options.along_track_step_m, options.along_track_range_m);
    o.effective_points = options.stereo_map_effective_points;
    o.cap_sigmas = std::max(3.0, options.stereo_map_truncation_sigmas);
    o.min_gain = options.along_track_min_gain;
    o.smooth_m = options.along_track_smooth_m;
    const AlongTrackFix fix = searchAlongTrack(field, start.T_map_body * T_body_cam, p_cam, sigma_m, o);
    if (!fix.found) return fix;
    widenAlongTrack(prior, fix, options.along_track_velocity_sigma_m_s);
    const Eigen::Vector3d shift = fix.shift_m * fix.direction_world;
    measurements.push_back(alongTrackMeasurement(fix, start.T_map_body, options.along_track_sigma_m));
    // The previous state and its prior's mean move with the fix: a prior left behind would pull the window back and
    // the velocity would carry the difference into the next prediction (a fix overshoots, the next one swings back).
    previous.T_map_body.translation() += shift;
    prior.mean.T_map_body.translation() += shift;
    start.T_map_body.translation() += shift;
    return fix;
}

}  // namespace quasiloc::tracking
