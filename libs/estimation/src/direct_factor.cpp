#include <algorithm>
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/estimation/direct_factor.h>
#include <quasiloc/estimation/pose_parametrization.h>

#include "direct_alignment_detail.h"
#include "parallel_points.h"

namespace quasiloc::estimation
{
namespace
{
const CameraEdgeLevel& checkedLevel(const CameraEdgeField& field, int level)
{
    core::require(level >= 0 && level < int(field.levels.size()), "DirectEdgeCostFunction level",
                  std::to_string(level) + " is not a level of the camera edge field (" +
                      std::to_string(field.levels.size()) + " levels)");
    return field.levels[size_t(level)];
}
}  // namespace

DirectEdgeCostFunction::DirectEdgeCostFunction(const CameraEdgeField& field, int level, const core::CameraModel& camera,
                                               const DirectAlignmentModel& model, const Eigen::Isometry3d& T_body_cam,
                                               double sigma_px, double truncation_px, double huber_px)
    : level_(checkedLevel(field, level)),
      camera_(camera),
      model_(model),
      T_cam_body_(T_body_cam.inverse()),
      inv_sigma_(1.0 / sigma_px),
      truncation_px_(truncation_px),
      flat_px_(truncation_px - 1e-3),
      huber_(huber_px / sigma_px)
{
    core::require(sigma_px > 0, "DirectEdgeCostFunction sigma_px", "must be > 0");
    core::require(huber_px > 0, "DirectEdgeCostFunction huber_px", "must be > 0");
    core::require(!model.edge_points_world.empty(), "DirectEdgeCostFunction model", "has no edge points");
    set_num_residuals(int(model.edge_points_world.size()));
    mutable_parameter_block_sizes()->push_back(kPoseSize);
}

bool DirectEdgeCostFunction::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const
{
    const Eigen::Isometry3d T_map_body = paramsToPose(parameters[0]);
    const Eigen::Isometry3d T_cam_map = T_cam_body_ * T_map_body.inverse();
    const Eigen::Matrix3d R_body_cam = T_cam_body_.linear().transpose();
    double* J = jacobians ? jacobians[0] : nullptr;
    detail::forPointStripes(model_.edge_points_world.size(), [&](size_t begin, size_t end) {
        evaluatePoints(begin, end, T_cam_map, R_body_cam, residuals, J);
    });
    return true;
}

void DirectEdgeCostFunction::evaluatePoints(size_t begin, size_t end, const Eigen::Isometry3d& T_cam_map,
                                            const Eigen::Matrix3d& R_body_cam, double* residuals, double* J) const
{
    for (size_t i = begin; i < end; ++i)
    {
        double* Ji = J ? J + i * kPoseSize : nullptr;
        if (Ji) std::fill(Ji, Ji + kPoseSize, 0.0);
        Eigen::Vector3d p_cam;
        Eigen::Vector2d u;
        Eigen::Matrix<double, 2, 3> J_u_p;
        if (!detail::projectToLevel(camera_, level_, T_cam_map, model_.edge_points_world[i], p_cam, u,
                                    Ji ? &J_u_p : nullptr))
        {
            residuals[i] = robust(flat_px_ * inv_sigma_, nullptr);
            continue;
        }
        const cv::Mat& D = level_.distance[model_.edge_bin[i]];
        const float x = float(u.x()), y = float(u.y());
        // The field is truncated where it was built; the factor may truncate lower.
        const double r = std::min<double>(detail::bilinear(D, x, y), truncation_px_);
        double slope = 0;
        residuals[i] = robust(r * inv_sigma_, &slope);
        if (!Ji || r >= flat_px_) continue;
        const Eigen::RowVector2d g(0.5 * (detail::bilinear(D, x + 1, y) - detail::bilinear(D, x - 1, y)),
                                   0.5 * (detail::bilinear(D, x, y + 1) - detail::bilinear(D, x, y - 1)));
        const Eigen::Vector3d p_body = R_body_cam * (p_cam - T_cam_body_.translation());
        const Eigen::Matrix<double, 1, 6> J6 =
            slope * inv_sigma_ * g * J_u_p * T_cam_body_.linear() * pointInBodyJacobian(p_body);
        for (int k = 0; k < 6; ++k) Ji[k] = J6[k];
    }
}

double DirectEdgeCostFunction::robust(double r, double* slope) const
{
    // rho = sqrt(2 huber(r)): |r| inside the threshold, sqrt(2 k |r| - k^2) beyond (r >= 0 here: a distance).
    if (r <= huber_)
    {
        if (slope) *slope = 1;
        return r;
    }
    const double rho = std::sqrt(2 * huber_ * r - huber_ * huber_);
    if (slope) *slope = huber_ / rho;
    return rho;
}

}  // namespace quasiloc::estimation
