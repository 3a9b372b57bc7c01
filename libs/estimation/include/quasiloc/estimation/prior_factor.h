#pragma once
// Gaussian priors on a frame state, the form the marginalisation of the previous window takes.
// Tangent order of a full state: [dtheta (3); dp (3); v (3); b_g (3); b_a (3)] (15), where the pose part
// follows pose_parametrization.h and the rest is Euclidean. The residual is r = S (x (-) x0) with
// S^T S = information; its Jacobian w.r.t. dtheta is S * Jr^-1(Log(R0^T R)), w.r.t. dp is S * R0^T R.
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <quasiloc/estimation/pose_parametrization.h>

namespace quasiloc::estimation
{
using Matrix15d = Eigen::Matrix<double, 15, 15>;
using Vector15d = Eigen::Matrix<double, 15, 1>;

/** A frame's state: pose T_map_body, velocity in the map frame, gyroscope and accelerometer biases. */
struct FrameState
{
    double t = 0;
    Eigen::Isometry3d T_map_body = Eigen::Isometry3d::Identity();
    Eigen::Vector3d v_map = Eigen::Vector3d::Zero();
    Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
    Eigen::Vector3d acc_bias = Eigen::Vector3d::Zero();
};

/** A Gaussian on a FrameState: mean and information in the tangent order above. */
struct StatePrior
{
    FrameState mean;
    Matrix15d information = Matrix15d::Zero();
};

/** Upper-triangular S with S^T S = information (eigen-clamped, so a PSD information with null directions
 *  is accepted; those directions stay free). */
Eigen::MatrixXd informationSqrt(const Eigen::MatrixXd& information);

/** 6 residuals on a pose block. */
class PosePriorFactor final : public ceres::SizedCostFunction<6, kPoseSize>
{
   public:
    PosePriorFactor(const Eigen::Isometry3d& T0_map_body, const Matrix6d& information);
    bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
    void linearize(const Eigen::Isometry3d& T, Vector6d& r, Matrix6d* J) const;

   private:
    Eigen::Isometry3d T0_;
    Matrix6d sqrt_info_;
};

/** 15 residuals on a (pose, speed_bias) pair. */
class StatePriorFactor final : public ceres::SizedCostFunction<15, kPoseSize, kSpeedBiasSize>
{
   public:
    explicit StatePriorFactor(const StatePrior& prior);
    bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
    void linearize(const Eigen::Isometry3d& T, const Eigen::Matrix<double, 9, 1>& sb, Vector15d& r,
                   Eigen::Matrix<double, 15, 6>* J_pose, Eigen::Matrix<double, 15, 9>* J_sb) const;

   private:
    Eigen::Isometry3d T0_;
    Eigen::Matrix<double, 9, 1> sb0_;
    Matrix15d sqrt_info_;
};

}  // namespace quasiloc::estimation
