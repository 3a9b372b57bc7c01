#pragma once
// The direct edge term of direct_alignment.h as a Ceres factor on the estimator's pose block, so that it can sit
// in the same optimisation as IMU, visual and map-feature factors instead of entering as a pose measurement
// computed beforehand.
//
// One residual per map edge point i of the model, at one pyramid level of the camera edge field:
//     d_i = DT_{bin_i}( pi( T_cam_map P_i ) ) / sigma_px,   T_cam_map = (T_map_body T_body_cam)^-1,
//     r_i = sqrt(2 huber_k(d_i)),  k = huber_px / sigma_px   (= d_i below k),
// DT = the truncated distance to the nearest camera edge of the point's orientation class (level pixels), so
// that 0.5 sum r_i^2 is exactly alignDirect's Huber cost. The Huber is inside the residual, not a
// ceres::LossFunction: Ceres' curvature correction zeroes the Jacobian of a one-dimensional residual in the
// linear part of a Huber (or soft-L1) loss, so points farther than k would not pull at all and the basin of
// convergence shrinks to k (measured: stuck at 8 cm from a 10 cm start where alignDirect reaches 2 cm). A point
// outside the image or on the flat (truncated) part of the field keeps a constant residual with a zero
// Jacobian: it neither pulls nor changes the minimiser. Jacobians are analytic, w.r.t. the right perturbation
// of pose_parametrization.h (lifted into the 7-wide block, PoseManifold).
#include <ceres/cost_function.h>

#include <Eigen/Geometry>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/estimation/direct_alignment.h>

namespace quasiloc::estimation
{
class DirectEdgeCostFunction final : public ceres::CostFunction
{
   public:
    /** field, camera and model must outlive the cost function. InputError for a level the field does not have,
     *  sigma_px <= 0, or a model without edge points. */
    DirectEdgeCostFunction(const CameraEdgeField& field, int level, const core::CameraModel& camera,
                           const DirectAlignmentModel& model, const Eigen::Isometry3d& T_body_cam, double sigma_px,
                           double truncation_px, double huber_px);
    bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

   private:
    const CameraEdgeLevel& level_;
    const core::CameraModel& camera_;
    const DirectAlignmentModel& model_;
    /** sqrt(2 huber(d)) and its derivative w.r.t. d. */
    double robust(double d, double* slope) const;
    /** Residuals (and Jacobian rows when J is set) of edge points [begin, end). */
    void evaluatePoints(size_t begin, size_t end, const Eigen::Isometry3d& T_cam_map, const Eigen::Matrix3d& R_body_cam,
                        double* residuals, double* J) const;

    Eigen::Isometry3d T_cam_body_;
    double inv_sigma_, truncation_px_, flat_px_, huber_;
};

}  // namespace quasiloc::estimation
