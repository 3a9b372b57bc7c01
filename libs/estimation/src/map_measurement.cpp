#include <Eigen/Eigenvalues>
#include <quasiloc/estimation/map_measurement.h>

namespace quasiloc::estimation
{
Matrix6d fixedMapInformation(double sigma_rad, double sigma_m)
{
    Vector6d info;
    info << Eigen::Vector3d::Constant(1.0 / (sigma_rad * sigma_rad)), Eigen::Vector3d::Constant(1.0 / (sigma_m * sigma_m));
    return info.asDiagonal();
}

Matrix6d observabilityMapInformation(const Matrix6d& H, double sigma_rad, double sigma_m)
{
    if (!H.allFinite() || H.norm() <= 0) return fixedMapInformation(sigma_rad, sigma_m);
    Vector6d d;
    d << Eigen::Vector3d::Constant(sigma_rad), Eigen::Vector3d::Constant(sigma_m);
    const Matrix6d Hn = d.asDiagonal() * (0.5 * (H + H.transpose())) * d.asDiagonal();
    const Eigen::SelfAdjointEigenSolver<Matrix6d> eig(Hn);
    const double l_max = eig.eigenvalues().maxCoeff();
    if (!(l_max > 0)) return fixedMapInformation(sigma_rad, sigma_m);
    const Vector6d l = (eig.eigenvalues() / l_max).cwiseMax(0.0);
    const Matrix6d shaped = eig.eigenvectors() * l.asDiagonal() * eig.eigenvectors().transpose();
    const Vector6d d_inv = d.cwiseInverse();
    return d_inv.asDiagonal() * shaped * d_inv.asDiagonal();
}

Matrix6d cameraToBodyInformation(const Matrix6d& I_cam, const Eigen::Isometry3d& T_body_cam)
{
    // T_map_cam (+) delta_cam = (T_map_body (+) delta_body) T_body_cam gives delta_cam = Ad(T_cam_body) delta_body,
    // in the [dtheta; dp] order: [[R, 0], [t^ R, R]] with (R, t) = T_cam_body.
    const Eigen::Isometry3d T_cam_body = T_body_cam.inverse();
    const Eigen::Matrix3d R = T_cam_body.linear();
    Matrix6d A = Matrix6d::Zero();
    A.topLeftCorner<3, 3>() = R;
    A.bottomRightCorner<3, 3>() = R;
    A.bottomLeftCorner<3, 3>() = hat(T_cam_body.translation()) * R;
    return A.transpose() * I_cam * A;
}

}  // namespace quasiloc::estimation
