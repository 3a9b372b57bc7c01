// Changes to the previous state's prior before a frame (zero_velocity_update.h).
#include <quasiloc/tracking/zero_velocity_update.h>

#include <Eigen/Dense>

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

}  // namespace quasiloc::tracking
