#pragma once
// The pose state of the estimator, its perturbation, and the SO(3) helpers the Jacobians use.
//
// STATE. Each frame's pose is T_map_body (the body = IMU frame in the map frame; the map frame is the IMU
// "world" frame, gravity along -z). It is stored as a Ceres parameter block of 7 doubles
// [qx qy qz qw tx ty tz] (Eigen quaternion order, then translation). The paper's T_t (P^C = T_t P^M) is
// T_cam_map = (T_map_body * T_body_cam)^-1; see camFromMap().
//
// PERTURBATION (right, in the body frame, rotation first):
//     delta = [dtheta; dp] (6),   R' = R Exp(dtheta),   t' = t + R dp.
// dtheta is a rotation about body axes (radians), dp a body-frame translation (metres). With
// T_body_cam = identity these are camera-frame directions, which is how the weak directions of the paper are
// stated (a point's viewing ray, a line's interpretation plane, a plane's normal).
//
// WHY [rotation; translation]. PAPER_NOTES scales the SECOND block by L in D = diag(I3, L I3). Changing the
// unit of length by a factor s multiplies dp by s and leaves dtheta unchanged, so a pixel residual's Jacobian
// has J_dp ~ 1/s and J_dtheta ~ 1; with L ~ s (L = median depth), J D = [J_dtheta, L J_dp] is unit-free.
// This only works if the second block is the translation, hence the ordering (derivation in reweighting.h).
//
// CERES. The visual and IMU cost functions compute Jacobians with respect to delta directly and write them
// into the first 6 columns of the 7-wide ambient Jacobian (last column zero); PoseManifold::PlusJacobian is
// [I6; 0]. Ceres multiplies the two, so it sees exactly d(residual)/d(delta) (the "lifted" Jacobian used by
// OKVIS/VINS; the unit tests check it against numeric differentiation through PoseManifold::Plus).
#include <ceres/manifold.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace quasiloc::estimation
{
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Matrix26d = Eigen::Matrix<double, 2, 6>;

constexpr int kPoseSize = 7;       ///< ambient size of a pose block
constexpr int kPoseDof = 6;        ///< tangent size [dtheta; dp]
constexpr int kSpeedBiasSize = 9;  ///< [v_map (3); gyro bias (3); accelerometer bias (3)]

Eigen::Matrix3d hat(const Eigen::Vector3d& v);
/** SO(3) exponential and logarithm (axis-angle vector <-> rotation matrix), stable near zero. */
Eigen::Matrix3d expSO3(const Eigen::Vector3d& phi);
Eigen::Vector3d logSO3(const Eigen::Matrix3d& R);
/** Right Jacobian of SO(3) and its inverse (Forster et al. 2017, eq. 8 and 9). */
Eigen::Matrix3d rightJacobianSO3(const Eigen::Vector3d& phi);
Eigen::Matrix3d rightJacobianInvSO3(const Eigen::Vector3d& phi);

/** Parameter block <-> isometry. */
void poseToParams(const Eigen::Isometry3d& T_map_body, double* params);
Eigen::Isometry3d paramsToPose(const double* params);

/** Diagonal information of a pose Gaussian with sigma_rad on every rotation axis and sigma_m on every translation
 *  axis, in the tangent order [dtheta; dp]. */
inline Vector6d poseInformationDiagonal(double sigma_rad, double sigma_m)
{
    Vector6d info;
    info << Eigen::Vector3d::Constant(1.0 / (sigma_rad * sigma_rad)),
        Eigen::Vector3d::Constant(1.0 / (sigma_m * sigma_m));
    return info;
}

/** T' = T (+) delta with the right perturbation above; and delta = T2 (-) T1 (so T1 (+) delta = T2). */
Eigen::Isometry3d boxPlus(const Eigen::Isometry3d& T, const Vector6d& delta);
Vector6d boxMinus(const Eigen::Isometry3d& T2, const Eigen::Isometry3d& T1);

/** The paper's T_t = T_cam_map from the state and the camera extrinsic. */
inline Eigen::Isometry3d camFromMap(const Eigen::Isometry3d& T_map_body, const Eigen::Isometry3d& T_body_cam)
{
    return (T_map_body * T_body_cam).inverse();
}

/** Ceres manifold of a pose block (see the file comment for the lifted Jacobian convention). */
class PoseManifold final : public ceres::Manifold
{
   public:
    int AmbientSize() const override { return kPoseSize; }
    int TangentSize() const override { return kPoseDof; }
    bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
    bool PlusJacobian(const double* x, double* jacobian) const override;
    bool Minus(const double* y, const double* x, double* y_minus_x) const override;
    bool MinusJacobian(const double* x, double* jacobian) const override;
};

/** d(p_body)/d(delta) for p_body = R^T (P_map - t), with the perturbation above: [hat(p_body), -I]. */
Eigen::Matrix<double, 3, 6> pointInBodyJacobian(const Eigen::Vector3d& p_body);

/** Writes a 6-column tangent Jacobian (row-major) into a 7-column lifted Ceres Jacobian (row-major). */
void liftPoseJacobian(const double* J6_rowmajor, int rows, double* J7_rowmajor);

}  // namespace quasiloc::estimation
