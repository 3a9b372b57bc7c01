#pragma once
// Visual residuals with analytic Jacobians against the pose block T_map_body (pose_parametrization.h).
// Every residual is whitened: r = sqrt(W_meas) * e, so J^T J is the information H = J_e^T W_meas J_e.
//
//   point        e = pi(T_cam_map P) - u                         2 residuals, pixels
//   point-line   e_m = l^T [pi(T_cam_map P_m); 1]                one per LiDAR support point P_m, pixels
//   point-plane  e_m = n^T (T_map_cam P^C_m) + d                 one per query stereo point, metres
//   stereo       e = [pi_L(T_left_map X) - u_L; pi_R(T_right_map X) - u_R]   landmark X is a variable
//
// A point that ends up behind the camera (z <= min depth) contributes a zero residual and a zero Jacobian
// rather than failing the evaluation: a bad step then shows up as no information, not as a solver abort.
// linearize() evaluates at any pose without Ceres (the reweighting and the unit tests use it).
// The reweighting's W*_i = w_i W_meas is applied outside the factor, as a ceres::ScaledLoss around the robust
// loss, so the robust threshold stays in units of the measurement sigma.
// The camera geometry is held by pointer: it must outlive the factor.
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/estimation/pose_parametrization.h>
#include <vector>

namespace quasiloc::estimation
{
/** The camera of the visual factors: intrinsics plus the extrinsic T_body_cam. */
struct CameraGeometry
{
    core::CameraModel model;
    Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();
};

class PointReprojectionFactor final : public ceres::SizedCostFunction<2, kPoseSize>
{
   public:
    PointReprojectionFactor(const CameraGeometry& camera, const Eigen::Vector2d& px, const Eigen::Vector3d& p_map,
                            double sigma_px);
    bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
    /** Whitened residual and d(residual)/d(delta) at T_map_body. False if the point is behind the camera. */
    bool linearize(const Eigen::Isometry3d& T_map_body, Eigen::Vector2d& r, Matrix26d* J) const;

   private:
    const CameraGeometry* camera_;
    Eigen::Vector2d px_;
    Eigen::Vector3d p_map_;
    double sqrt_info_;
};

class PointToLineFactor final : public ceres::SizedCostFunction<ceres::DYNAMIC, kPoseSize>
{
   public:
    /** line_px: homogeneous image line, normalised here so that line_px.head<2>() has unit length. */
    PointToLineFactor(const CameraGeometry& camera, const Eigen::Vector3d& line_px,
                      std::vector<Eigen::Vector3d> support_map, double sigma_px);
    bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
    void linearize(const Eigen::Isometry3d& T_map_body, Eigen::VectorXd& r, Eigen::Matrix<double, -1, 6>* J) const;

   private:
    const CameraGeometry* camera_;
    Eigen::Vector3d line_;
    std::vector<Eigen::Vector3d> support_map_;
    double sqrt_info_;
};

class PointToPlaneFactor final : public ceres::SizedCostFunction<ceres::DYNAMIC, kPoseSize>
{
   public:
    PointToPlaneFactor(const CameraGeometry& camera, std::vector<Eigen::Vector3d> points_cam,
                       const Eigen::Vector3d& n_map, double d, double sigma_m);
    bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
    void linearize(const Eigen::Isometry3d& T_map_body, Eigen::VectorXd& r, Eigen::Matrix<double, -1, 6>* J) const;

   private:
    std::vector<Eigen::Vector3d> points_body_;  ///< T_body_cam P^C, precomputed
    Eigen::Vector3d n_map_;
    double d_;
    double sqrt_info_;
};

/** A stereo camera for temporal landmarks: left camera (with T_body_cam) and right camera with T_left_right. */
struct StereoGeometry
{
    CameraGeometry left;
    core::CameraModel right;
    Eigen::Isometry3d T_left_right = Eigen::Isometry3d::Identity();
};

/** Stereo reprojection of a landmark (parameter block: X in the map frame, 3 doubles) in one frame. */
class StereoLandmarkFactor final : public ceres::SizedCostFunction<4, kPoseSize, 3>
{
   public:
    StereoLandmarkFactor(const StereoGeometry& stereo, const Eigen::Vector2d& left_px, const Eigen::Vector2d& right_px,
                         double sigma_px);
    bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
    bool linearize(const Eigen::Isometry3d& T_map_body, const Eigen::Vector3d& X_map, Eigen::Vector4d& r,
                   Eigen::Matrix<double, 4, 6>* J_pose, Eigen::Matrix<double, 4, 3>* J_landmark) const;

   private:
    const StereoGeometry* stereo_;
    Eigen::Vector2d left_px_, right_px_;
    double sqrt_info_;
};

}  // namespace quasiloc::estimation
