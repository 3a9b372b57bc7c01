#include <quasiloc/estimation/estimator_options.h>

namespace quasiloc::estimation
{
void EstimatorOptions::declare(core::OptionTable& t)
{
    using core::Range;
    t.addEnum("primitives", primitives,
              {{"P", Primitives::P}, {"L", Primitives::L}, {"P+L", Primitives::PL}, {"P+L+plane", Primitives::PLPlane}},
              "which structural residuals enter (ablation)");
    t.add("use_imu", use_imu, "IMU preintegration and bias random-walk factors (when the input has them)");
    t.add("use_temporal_landmarks", use_temporal_landmarks,
          "stereo reprojection of landmarks seen in the previous and the current frame");
    t.add("outer_iterations", outer_iterations, "", Range::between(1, 100),
          "relinearise + reweight + solve rounds (weights fixed within a round)");
    t.add("inner_iterations", inner_iterations, "", Range::between(1, 1000),
          "Levenberg-Marquardt iterations per round");
    t.addEnum("robust_loss", robust_loss,
              {{"none", RobustLoss::None}, {"huber", RobustLoss::Huber}, {"cauchy", RobustLoss::Cauchy}},
              "robust loss on whitened residuals");
    t.add("robust_threshold", robust_threshold, "", Range::above(0),
          "in sigmas of a single residual; a block of n residuals uses sqrt(n) times it");
    t.add("min_depth_m", min_depth_m, "m", Range::atLeast(0),
          "map matches closer than this (camera z) do not count for L");
    t.add("marginal_damping", marginal_damping, "", Range::atLeast(0),
          "added to the diagonal of the marginalised block (gauge, unseen landmarks)");
    t.add("imu_gap_s", imu_gap_s, "s", Range::above(0),
          "a step between two IMU samples longer than this is a gap (dropped samples): its motion was not measured");
    t.add("imu_gap_max_s", imu_gap_max_s, "s", Range::above(0),
          "longer gaps get no added variance: the loss check and the relocalization handle them");
    t.add("imu_gap_acc_sigma", imu_gap_acc_sigma, "m/s^2", Range::atLeast(0),
          "unmeasured acceleration in a gap: added to the step's variance (0: the held sample is trusted)");
    t.add("imu_gap_gyro_sigma", imu_gap_gyro_sigma, "rad/s", Range::atLeast(0),
          "unmeasured angular rate in a gap: added to the step's variance");
}

void EstimatorOptions::check(const std::string& input) const { checkRanges(input, "Estimator"); }

}  // namespace quasiloc::estimation
