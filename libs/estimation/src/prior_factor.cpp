#include <Eigen/Eigenvalues>
#include <quasiloc/estimation/prior_factor.h>

namespace quasiloc::estimation
{
Eigen::MatrixXd informationSqrt(const Eigen::MatrixXd& information)
{
    // Eigen-decomposition rather than Cholesky: a marginal information may be singular (e.g. yaw and
    // position of a visual-only window without map factors); S = diag(sqrt(max(l, 0))) U^T.
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (information + information.transpose()));
    const Eigen::VectorXd s = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt();
    return s.asDiagonal() * eig.eigenvectors().transpose();
}

namespace
{
/** r_pose = [Log(R0^T R); R0^T (t - t0)] and its Jacobian w.r.t. [dtheta; dp]. */
Vector6d poseError(const Eigen::Isometry3d& T0, const Eigen::Isometry3d& T, Matrix6d* J)
{
    const Vector6d e = boxMinus(T, T0);
    if (J)
    {
        J->setZero();
        J->topLeftCorner<3, 3>() = rightJacobianInvSO3(e.head<3>());
        J->bottomRightCorner<3, 3>() = T0.linear().transpose() * T.linear();
    }
    return e;
}
}  // namespace

PosePriorFactor::PosePriorFactor(const Eigen::Isometry3d& T0, const Matrix6d& information)
    : T0_(T0), sqrt_info_(informationSqrt(information))
{}

void PosePriorFactor::linearize(const Eigen::Isometry3d& T, Vector6d& r, Matrix6d* J) const
{
    Matrix6d Je;
    r = sqrt_info_ * poseError(T0_, T, J ? &Je : nullptr);
    if (J) *J = sqrt_info_ * Je;
}

bool PosePriorFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const
{
    Vector6d r;
    Matrix6d J;
    const bool want = jacobians && jacobians[0];
    linearize(paramsToPose(parameters[0]), r, want ? &J : nullptr);
    Eigen::Map<Vector6d>{residuals} = r;
    if (want) liftPoseJacobian(Eigen::Matrix<double, 6, 6, Eigen::RowMajor>(J).data(), 6, jacobians[0]);
    return true;
}

StatePriorFactor::StatePriorFactor(const StatePrior& prior)
    : T0_(prior.mean.T_map_body), sqrt_info_(informationSqrt(prior.information))
{
    sb0_ << prior.mean.v_map, prior.mean.gyro_bias, prior.mean.acc_bias;
}

void StatePriorFactor::linearize(const Eigen::Isometry3d& T, const Eigen::Matrix<double, 9, 1>& sb, Vector15d& r,
                                 Eigen::Matrix<double, 15, 6>* J_pose, Eigen::Matrix<double, 15, 9>* J_sb) const
{
    Matrix6d Je;
    Vector15d e;
    e.head<6>() = poseError(T0_, T, &Je);
    e.tail<9>() = sb - sb0_;
    r = sqrt_info_ * e;
    if (J_pose) *J_pose = sqrt_info_.leftCols<6>() * Je;
    if (J_sb) *J_sb = sqrt_info_.rightCols<9>();
}

bool StatePriorFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const
{
    Vector15d r;
    Eigen::Matrix<double, 15, 6> Jp;
    Eigen::Matrix<double, 15, 9> Js;
    const bool want_p = jacobians && jacobians[0], want_s = jacobians && jacobians[1];
    linearize(paramsToPose(parameters[0]), Eigen::Map<const Eigen::Matrix<double, 9, 1>>(parameters[1]), r,
              want_p ? &Jp : nullptr, want_s ? &Js : nullptr);
    Eigen::Map<Vector15d>{residuals} = r;
    if (want_p) liftPoseJacobian(Eigen::Matrix<double, 15, 6, Eigen::RowMajor>(Jp).data(), 15, jacobians[0]);
    if (want_s) Eigen::Map<Eigen::Matrix<double, 15, 9, Eigen::RowMajor>>{jacobians[1]} = Js;
    return true;
}

}  // namespace quasiloc::estimation
