#include <cmath>
#include <quasiloc/estimation/pose_parametrization.h>

namespace quasiloc::estimation
{
Eigen::Matrix3d hat(const Eigen::Vector3d& v)
{
    Eigen::Matrix3d m;
    m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
    return m;
}

Eigen::Matrix3d expSO3(const Eigen::Vector3d& phi)
{
    const double theta = phi.norm();
    if (theta < 1e-8) return Eigen::Matrix3d::Identity() + hat(phi);
    return Eigen::AngleAxisd(theta, phi / theta).toRotationMatrix();
}

Eigen::Vector3d logSO3(const Eigen::Matrix3d& R)
{
    // Through the quaternion: accurate near 0 and near pi, unlike acos((trace - 1) / 2).
    Eigen::Quaterniond q(R);
    q.normalize();
    if (q.w() < 0) q.coeffs() *= -1;
    const Eigen::Vector3d v = q.vec();
    const double s = v.norm();
    if (s < 1e-10) return 2.0 * v;
    return (2.0 * std::atan2(s, q.w()) / s) * v;
}

Eigen::Matrix3d rightJacobianSO3(const Eigen::Vector3d& phi)
{
    const double theta = phi.norm();
    const Eigen::Matrix3d W = hat(phi);
    if (theta < 1e-5) return Eigen::Matrix3d::Identity() - 0.5 * W + W * W / 6.0;
    const double t2 = theta * theta;
    return Eigen::Matrix3d::Identity() - (1 - std::cos(theta)) / t2 * W +
           (theta - std::sin(theta)) / (t2 * theta) * W * W;
}

Eigen::Matrix3d rightJacobianInvSO3(const Eigen::Vector3d& phi)
{
    const double theta = phi.norm();
    const Eigen::Matrix3d W = hat(phi);
    if (theta < 1e-5) return Eigen::Matrix3d::Identity() + 0.5 * W + W * W / 12.0;
    const double t2 = theta * theta;
    return Eigen::Matrix3d::Identity() + 0.5 * W +
           (1.0 / t2 - (1 + std::cos(theta)) / (2 * theta * std::sin(theta))) * W * W;
}

void poseToParams(const Eigen::Isometry3d& T, double* params)
{
    Eigen::Quaterniond q(T.linear());
    q.normalize();
    Eigen::Map<Eigen::Vector4d>{params} = q.coeffs();
    Eigen::Map<Eigen::Vector3d>(params + 4) = T.translation();
}

Eigen::Isometry3d paramsToPose(const double* params)
{
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::Map<const Eigen::Quaterniond>(params).normalized().toRotationMatrix();
    T.translation() = Eigen::Map<const Eigen::Vector3d>(params + 4);
    return T;
}

Eigen::Isometry3d boxPlus(const Eigen::Isometry3d& T, const Vector6d& delta)
{
    Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
    out.linear() = T.linear() * expSO3(delta.head<3>());
    out.translation() = T.translation() + T.linear() * delta.tail<3>();
    return out;
}

Vector6d boxMinus(const Eigen::Isometry3d& T2, const Eigen::Isometry3d& T1)
{
    Vector6d d;
    d.head<3>() = logSO3(T1.linear().transpose() * T2.linear());
    d.tail<3>() = T1.linear().transpose() * (T2.translation() - T1.translation());
    return d;
}

bool PoseManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const
{
    poseToParams(boxPlus(paramsToPose(x), Eigen::Map<const Vector6d>(delta)), x_plus_delta);
    return true;
}

bool PoseManifold::PlusJacobian(const double*, double* jacobian) const
{
    Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> J(jacobian);
    J.setZero();
    J.topRows<6>().setIdentity();
    return true;
}

bool PoseManifold::Minus(const double* y, const double* x, double* y_minus_x) const
{
    Eigen::Map<Vector6d>{y_minus_x} = boxMinus(paramsToPose(y), paramsToPose(x));
    return true;
}

bool PoseManifold::MinusJacobian(const double*, double* jacobian) const
{
    // Consistent with the lifted PlusJacobian: MinusJacobian * PlusJacobian = I6.
    Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> J(jacobian);
    J.setZero();
    J.leftCols<6>().setIdentity();
    return true;
}

Eigen::Matrix<double, 3, 6> pointInBodyJacobian(const Eigen::Vector3d& p_body)
{
    Eigen::Matrix<double, 3, 6> J;
    J.leftCols<3>() = hat(p_body);
    J.rightCols<3>() = -Eigen::Matrix3d::Identity();
    return J;
}

void liftPoseJacobian(const double* J6, int rows, double* J7)
{
    for (int r = 0; r < rows; ++r)
    {
        for (int c = 0; c < 6; ++c) J7[r * 7 + c] = J6[r * 6 + c];
        J7[r * 7 + 6] = 0.0;
    }
}

}  // namespace quasiloc::estimation
