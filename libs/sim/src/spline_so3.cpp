#include "spline_so3.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>

namespace quasiloc::sim::spline
{
Eigen::Matrix3d skew(const Eigen::Vector3d& w)
{
    Eigen::Matrix3d S;
    S << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
    return S;
}

Eigen::Matrix3d expSO3(const Eigen::Vector3d& w)
{
    const double theta2 = w.squaredNorm();
    const Eigen::Matrix3d W = skew(w);
    if (theta2 < 1e-16) return Eigen::Matrix3d::Identity() + W + 0.5 * W * W;
    const double theta = std::sqrt(theta2);
    return Eigen::Matrix3d::Identity() + (std::sin(theta) / theta) * W + ((1 - std::cos(theta)) / theta2) * W * W;
}

Eigen::Vector3d logSO3(const Eigen::Matrix3d& R)
{
    // Through the quaternion: accurate for small angles and stable up to pi.
    Eigen::Quaterniond q(R);
    if (q.w() < 0) q.coeffs() *= -1;
    const double s = q.vec().norm();
    if (s < 1e-12) return 2.0 * q.vec() / q.w();
    const double angle = 2.0 * std::atan2(s, q.w());
    return (angle / s) * q.vec();
}

Eigen::Matrix3d rightJacobian(const Eigen::Vector3d& w)
{
    const double theta2 = w.squaredNorm();
    const Eigen::Matrix3d W = skew(w);
    if (theta2 < 1e-10) return Eigen::Matrix3d::Identity() - 0.5 * W + (1.0 / 6.0) * W * W;
    const double theta = std::sqrt(theta2);
    return Eigen::Matrix3d::Identity() - ((1 - std::cos(theta)) / theta2) * W +
           ((theta - std::sin(theta)) / (theta2 * theta)) * W * W;
}

Eigen::Matrix3d rightJacobianInverse(const Eigen::Vector3d& w)
{
    const double theta2 = w.squaredNorm();
    const Eigen::Matrix3d W = skew(w);
    if (theta2 < 1e-10) return Eigen::Matrix3d::Identity() + 0.5 * W + (1.0 / 12.0) * W * W;
    const double theta = std::sqrt(theta2);
    const double c = 1.0 / theta2 - (1 + std::cos(theta)) / (2 * theta * std::sin(theta));
    return Eigen::Matrix3d::Identity() + 0.5 * W + c * W * W;
}

Eigen::Matrix3d orthonormalize(const Eigen::Matrix3d& R)
{
    return Eigen::Quaterniond(R).normalized().toRotationMatrix();
}

CubicBasis::CubicBasis(double u)
{
    const double u2 = u * u, u3 = u2 * u, v = 1 - u;
    b = {v * v * v / 6, (3 * u3 - 6 * u2 + 4) / 6, (-3 * u3 + 3 * u2 + 3 * u + 1) / 6, u3 / 6};
    db = {-v * v / 2, 1.5 * u2 - 2 * u, -1.5 * u2 + u + 0.5, u2 / 2};
    ddb = {v, 3 * u - 2, -3 * u + 1, u};
}

namespace
{
std::array<double, 4> cumulativeOf(const std::array<double, 4>& x, double first)
{
    return {first, x[1] + x[2] + x[3], x[2] + x[3], x[3]};
}
}  // namespace

std::array<double, 4> CubicBasis::cumulative() const { return cumulativeOf(b, 1.0); }
std::array<double, 4> CubicBasis::cumulativeD() const { return cumulativeOf(db, 0.0); }
std::array<double, 4> CubicBasis::cumulativeDD() const { return cumulativeOf(ddb, 0.0); }

}  // namespace quasiloc::sim::spline
