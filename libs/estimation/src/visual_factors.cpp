#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/estimation/visual_factors.h>

namespace quasiloc::estimation
{
namespace
{
constexpr double kMinDepth = 1e-3;

using RowMajor6 = Eigen::Matrix<double, -1, 6, Eigen::RowMajor>;

double sqrtInfo(double sigma, const char* what)
{
    core::require(std::isfinite(sigma) && sigma > 0, what, "sigma must be finite and > 0");
    return 1.0 / sigma;
}

/** Camera-frame point and d(p_cam)/d(delta) for the state T_map_body and extrinsic T_body_cam. */
Eigen::Vector3d pointInCamera(const Eigen::Isometry3d& T_map_body, const Eigen::Isometry3d& T_body_cam,
                              const Eigen::Vector3d& p_map, Eigen::Matrix<double, 3, 6>* J)
{
    const Eigen::Vector3d p_body = T_map_body.linear().transpose() * (p_map - T_map_body.translation());
    const Eigen::Matrix3d R_cam_body = T_body_cam.linear().transpose();
    if (J) *J = R_cam_body * pointInBodyJacobian(p_body);
    return R_cam_body * (p_body - T_body_cam.translation());
}

/** Ceres Evaluate of a structural factor (point-to-line, point-to-plane) from its linearize(): residuals, and the
 *  tangent Jacobian lifted into the 7-wide pose block. */
template <class Factor>
bool evaluateStructural(const Factor& f, double const* const* parameters, double* residuals, double** jacobians)
{
    Eigen::VectorXd r;
    Eigen::Matrix<double, -1, 6> J;
    const bool want_J = jacobians && jacobians[0];
    f.linearize(paramsToPose(parameters[0]), r, want_J ? &J : nullptr);
    Eigen::Map<Eigen::VectorXd>(residuals, r.size()) = r;
    if (want_J)
    {
        const RowMajor6 Jr = J;
        liftPoseJacobian(Jr.data(), static_cast<int>(r.size()), jacobians[0]);
    }
    return true;
}
}  // namespace

// ---------------------------------------------------------------------------------------------- point
PointReprojectionFactor::PointReprojectionFactor(const CameraGeometry& camera, const Eigen::Vector2d& px,
                                                 const Eigen::Vector3d& p_map, double sigma_px)
    : camera_(&camera), px_(px), p_map_(p_map), sqrt_info_(sqrtInfo(sigma_px, "PointMatch.sigma_px"))
{}

bool PointReprojectionFactor::linearize(const Eigen::Isometry3d& T, Eigen::Vector2d& r, Matrix26d* J) const
{
    Eigen::Matrix<double, 3, 6> J_p;
    const Eigen::Vector3d p_cam = pointInCamera(T, camera_->T_body_cam, p_map_, J ? &J_p : nullptr);
    Eigen::Vector2d u;
    Eigen::Matrix<double, 2, 3> J_u;
    if (!camera_->model.project(p_cam, u, &J_u, kMinDepth))
    {
        r.setZero();
        if (J) J->setZero();
        return false;
    }
    r = sqrt_info_ * (u - px_);
    if (J) *J = sqrt_info_ * J_u * J_p;
    return true;
}

bool PointReprojectionFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const
{
    Eigen::Vector2d r;
    Eigen::Matrix<double, 2, 6, Eigen::RowMajor> J;
    Matrix26d Jc;
    const bool want_J = jacobians && jacobians[0];
    linearize(paramsToPose(parameters[0]), r, want_J ? &Jc : nullptr);
    Eigen::Map<Eigen::Vector2d>{residuals} = r;
    if (want_J)
    {
        J = Jc;
        liftPoseJacobian(J.data(), 2, jacobians[0]);
    }
    return true;
}

// ----------------------------------------------------------------------------------------------- line
PointToLineFactor::PointToLineFactor(const CameraGeometry& camera, const Eigen::Vector3d& line_px,
                                     std::vector<Eigen::Vector3d> support_map, double sigma_px)
    : camera_(&camera), support_map_(std::move(support_map))
{
    const double n = line_px.head<2>().norm();
    core::require(std::isfinite(n) && n > 0, "LineFactorInput.line_px", "the line has no direction (a = b = 0)");
    core::require(!support_map_.empty(), "LineCandidate.support_map", "a line candidate has no support point");
    line_ = line_px / n;
    sqrt_info_ = sqrtInfo(sigma_px, "LineFactorInput.sigma_px");
    set_num_residuals(static_cast<int>(support_map_.size()));
}

void PointToLineFactor::linearize(const Eigen::Isometry3d& T, Eigen::VectorXd& r, Eigen::Matrix<double, -1, 6>* J) const
{
    const int n = static_cast<int>(support_map_.size());
    r.resize(n);
    if (J) J->resize(n, 6);
    for (int m = 0; m < n; ++m)
    {
        Eigen::Matrix<double, 3, 6> J_p;
        const Eigen::Vector3d p_cam = pointInCamera(T, camera_->T_body_cam, support_map_[m], J ? &J_p : nullptr);
        Eigen::Vector2d u;
        Eigen::Matrix<double, 2, 3> J_u;
        if (!camera_->model.project(p_cam, u, &J_u, kMinDepth))
        {
            r[m] = 0;
            if (J) J->row(m).setZero();
            continue;
        }
        r[m] = sqrt_info_ * (line_.head<2>().dot(u) + line_.z());
        if (J) J->row(m) = sqrt_info_ * line_.head<2>().transpose() * J_u * J_p;
    }
}

bool PointToLineFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const
{
    return evaluateStructural(*this, parameters, residuals, jacobians);
}

// ---------------------------------------------------------------------------------------------- plane
PointToPlaneFactor::PointToPlaneFactor(const CameraGeometry& camera, std::vector<Eigen::Vector3d> points_cam,
                                       const Eigen::Vector3d& n_map, double d, double sigma_m)
    : d_(d)
{
    const double nn = n_map.norm();
    core::require(std::isfinite(nn) && nn > 0, "PlaneCandidate.n_map", "the plane normal is zero or not finite");
    core::require(!points_cam.empty(), "PlaneFactorInput.points_cam", "a plane factor has no query point");
    n_map_ = n_map / nn;
    d_ = d / nn;
    points_body_.reserve(points_cam.size());
    for (const auto& p : points_cam) points_body_.push_back(camera.T_body_cam * p);
    sqrt_info_ = sqrtInfo(sigma_m, "PlaneFactorInput.sigma_m");
    set_num_residuals(static_cast<int>(points_body_.size()));
}

void PointToPlaneFactor::linearize(const Eigen::Isometry3d& T, Eigen::VectorXd& r,
                                   Eigen::Matrix<double, -1, 6>* J) const
{
    // P_map = R p_body + t; with R' = R Exp(dtheta), t' = t + R dp: dP = R (-hat(p_body) dtheta + dp).
    const int n = static_cast<int>(points_body_.size());
    r.resize(n);
    if (J) J->resize(n, 6);
    const Eigen::RowVector3d nR = n_map_.transpose() * T.linear();
    for (int m = 0; m < n; ++m)
    {
        const Eigen::Vector3d& pb = points_body_[m];
        r[m] = sqrt_info_ * (n_map_.dot(T * pb) + d_);
        if (J)
        {
            J->row(m).head<3>() = -sqrt_info_ * nR * hat(pb);
            J->row(m).tail<3>() = sqrt_info_ * nR;
        }
    }
}

bool PointToPlaneFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const
{
    return evaluateStructural(*this, parameters, residuals, jacobians);
}

// --------------------------------------------------------------------------------------------- stereo
StereoLandmarkFactor::StereoLandmarkFactor(const StereoGeometry& stereo, const Eigen::Vector2d& left_px,
                                           const Eigen::Vector2d& right_px, double sigma_px)
    : stereo_(&stereo),
      left_px_(left_px),
      right_px_(right_px),
      sqrt_info_(sqrtInfo(sigma_px, "TemporalLandmark.sigma_px"))
{}

bool StereoLandmarkFactor::linearize(const Eigen::Isometry3d& T, const Eigen::Vector3d& X, Eigen::Vector4d& r,
                                     Eigen::Matrix<double, 4, 6>* J_pose, Eigen::Matrix<double, 4, 3>* J_lm) const
{
    Eigen::Matrix<double, 3, 6> J_l;
    const Eigen::Vector3d p_left = pointInCamera(T, stereo_->left.T_body_cam, X, &J_l);
    const Eigen::Matrix3d R_right_left = stereo_->T_left_right.linear().transpose();
    const Eigen::Vector3d p_right = R_right_left * (p_left - stereo_->T_left_right.translation());
    // d(p_left)/dX = R_cam_body R_map_body^T.
    const Eigen::Matrix3d dL_dX = stereo_->left.T_body_cam.linear().transpose() * T.linear().transpose();
    Eigen::Vector2d uL, uR;
    Eigen::Matrix<double, 2, 3> JuL, JuR;
    if (!stereo_->left.model.project(p_left, uL, &JuL, kMinDepth) ||
        !stereo_->right.project(p_right, uR, &JuR, kMinDepth))
    {
        r.setZero();
        if (J_pose) J_pose->setZero();
        if (J_lm) J_lm->setZero();
        return false;
    }
    r << sqrt_info_ * (uL - left_px_), sqrt_info_ * (uR - right_px_);
    if (J_pose)
    {
        J_pose->topRows<2>() = sqrt_info_ * JuL * J_l;
        J_pose->bottomRows<2>() = sqrt_info_ * JuR * R_right_left * J_l;
    }
    if (J_lm)
    {
        J_lm->topRows<2>() = sqrt_info_ * JuL * dL_dX;
        J_lm->bottomRows<2>() = sqrt_info_ * JuR * R_right_left * dL_dX;
    }
    return true;
}

bool StereoLandmarkFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const
{
    Eigen::Vector4d r;
    Eigen::Matrix<double, 4, 6> Jp;
    Eigen::Matrix<double, 4, 3> Jl;
    const bool want_pose = jacobians && jacobians[0], want_lm = jacobians && jacobians[1];
    linearize(paramsToPose(parameters[0]), Eigen::Map<const Eigen::Vector3d>(parameters[1]), r,
              want_pose ? &Jp : nullptr, want_lm ? &Jl : nullptr);
    Eigen::Map<Eigen::Vector4d>{residuals} = r;
    if (want_pose)
    {
        const Eigen::Matrix<double, 4, 6, Eigen::RowMajor> Jr = Jp;
        liftPoseJacobian(Jr.data(), 4, jacobians[0]);
    }
    if (want_lm) Eigen::Map<Eigen::Matrix<double, 4, 3, Eigen::RowMajor>>{jacobians[1]} = Jl;
    return true;
}

}  // namespace quasiloc::estimation
