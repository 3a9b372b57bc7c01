// Changes to the previous state's prior before a frame (zero_velocity_update.h).
#include <quasiloc/tracking/zero_velocity_update.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace quasiloc::tracking
{
namespace
{
constexpr int kVelocity = 6;  ///< first tangent coordinate of the velocity
}  // namespace

void resetBlock(estimation::StatePrior& prior, int first, double sigma)
{
    prior.information.middleRows(first, 3).setZero();
    prior.information.middleCols(first, 3).setZero();
    prior.information.block<3, 3>(first, first) = Eigen::Matrix3d::Identity() / (sigma * sigma);
}

void applyZeroVelocity(estimation::FrameState& state, estimation::StatePrior& prior, double sigma_v)
{
    state.v_map.setZero();
    prior.mean.v_map.setZero();
    resetBlock(prior, kVelocity, sigma_v);
}

void widenVelocity(estimation::StatePrior& prior, double variance)
{
    if (variance <= 0) return;
    const estimation::Matrix15d identity = estimation::Matrix15d::Identity();
    const Eigen::LDLT<estimation::Matrix15d> information(prior.information);
    estimation::Matrix15d covariance = information.solve(identity);
    covariance.block<3, 3>(kVelocity, kVelocity) += variance * Eigen::Matrix3d::Identity();
    const estimation::Matrix15d widened = covariance.ldlt().solve(identity);
    prior.information = 0.5 * (widened + widened.transpose());
}

double medianImageMotionPx(const std::vector<cv::KeyPoint>& previous, const std::vector<cv::KeyPoint>& current,
                           const std::vector<frontend::PointMatch>& matches, size_t min_matches)
{
    std::vector<double> motion;
    motion.reserve(matches.size());
    for (const frontend::PointMatch& m : matches)
        if (m.query >= 0 && m.train >= 0 && size_t(m.query) < previous.size() && size_t(m.train) < current.size())
        {
            const cv::Point2f d = current[size_t(m.train)].pt - previous[size_t(m.query)].pt;
            motion.push_back(std::hypot(d.x, d.y));
        }
    if (motion.empty() || motion.size() < min_matches) return NAN;
    const auto middle = motion.begin() + long(motion.size() / 2);
    std::nth_element(motion.begin(), middle, motion.end());
    return *middle;
}

double KeypointTracks::add(const void* previous_id, const std::vector<cv::KeyPoint>& previous, const void* current_id,
                           const std::vector<cv::KeyPoint>& current, const std::vector<frontend::PointMatch>& matches,
                           int min_frames, size_t min_tracks)
{
    if (previous_id != last_id_ || origins_.size() != previous.size())
    {
        origins_.clear();
        for (const cv::KeyPoint& k : previous) origins_.push_back({k.pt, 0});
    }
    std::vector<Origin> next;
    next.reserve(current.size());
    for (const cv::KeyPoint& k : current) next.push_back({k.pt, 0});
    std::vector<double> motion;
    for (const frontend::PointMatch& m : matches)
    {
        if (m.query < 0 || m.train < 0 || size_t(m.query) >= origins_.size() || size_t(m.train) >= next.size())
            continue;
        Origin& o = next[size_t(m.train)];
        o = {origins_[size_t(m.query)].pt, origins_[size_t(m.query)].frames + 1};
        if (o.frames >= min_frames)
        {
            const cv::Point2f d = current[size_t(m.train)].pt - o.pt;
            motion.push_back(std::hypot(d.x, d.y));
        }
    }
    origins_ = std::move(next);
    last_id_ = current_id;
    if (motion.empty() || motion.size() < min_tracks) return NAN;
    const auto middle = motion.begin() + long(motion.size() / 2);
    std::nth_element(motion.begin(), middle, motion.end());
    return *middle;
}

}  // namespace quasiloc::tracking
