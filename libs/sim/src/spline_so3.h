#pragma once
// SO(3) helpers and the uniform cubic B-spline basis shared by the trajectory spline (private to libs/sim).
#include <Eigen/Core>
#include <array>

namespace quasiloc::sim::spline
{
Eigen::Matrix3d skew(const Eigen::Vector3d& w);
Eigen::Matrix3d expSO3(const Eigen::Vector3d& w);
Eigen::Vector3d logSO3(const Eigen::Matrix3d& R);
/** Right Jacobian of SO(3): Exp(w + dw) ~= Exp(w) Exp(Jr(w) dw). */
Eigen::Matrix3d rightJacobian(const Eigen::Vector3d& w);
Eigen::Matrix3d rightJacobianInverse(const Eigen::Vector3d& w);
/** Closest rotation matrix (removes the drift of long products). */
Eigen::Matrix3d orthonormalize(const Eigen::Matrix3d& R);

/** Uniform cubic B-spline basis at u in [0, 1] and its first two derivatives with respect to u:
 *  value = sum_j b[j] * c[k + j]. The cumulative basis used on SO(3) is lambda_j = sum_{m >= j} b[m]. */
struct CubicBasis
{
    std::array<double, 4> b, db, ddb;
    explicit CubicBasis(double u);
    /** Cumulative basis lambda_j (j = 1..3; index 0 is 1) and derivatives. */
    std::array<double, 4> cumulative() const;
    std::array<double, 4> cumulativeD() const;
    std::array<double, 4> cumulativeDD() const;
};

}  // namespace quasiloc::sim::spline
