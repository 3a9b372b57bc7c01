#include <ceres/loss_function.h>
#include <ceres/problem.h>
#include <ceres/solver.h>
#include <mrpt/system/CTicTac.h>

#include <quasiloc/core/error.h>
#include <quasiloc/estimation/direct_factor.h>
#include <quasiloc/estimation/pose_parametrization.h>
#include <quasiloc/estimation/prior_factor.h>

#include "direct_alignment_detail.h"

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
    for (size_t i = 0; i < model_.edge_points_world.size(); ++i)
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
    return true;
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

bool alignDirectCeres(const DirectAlignmentOptions& o, const CameraEdgeField& field, const core::CameraModel& camera,
                      const DirectAlignmentModel& model, Eigen::Isometry3d& T_world_cam, DirectAlignmentStats* stats,
                      const DirectPrior* prior)
{
    mrpt::system::CTicTac tic;
    DirectAlignmentStats st;
    if (!detail::canAlign(field, model, st, stats)) return false;
    st.initial_edge_cost = edgeCost(o, field, 0, camera, model, T_world_cam);
    double params[kPoseSize];
    poseToParams(T_world_cam, params);
    bool any_step = false;
    const double n = double(model.edge_points_world.size());
    // One Ceres solve per level, as alignDirect.
    const auto solveLevel = [&](int l, const detail::Robustness& kernel, const DirectPrior* level_prior) {
        PoseManifold manifold;  // declared before the problem that points to it, so it outlives it
        ceres::Problem::Options po;
        po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
        ceres::Problem problem(po);
        // The body is the camera here: the block is T_world_cam itself.
        problem.AddResidualBlock(new DirectEdgeCostFunction(field, l, camera, model, Eigen::Isometry3d::Identity(), 1.0,
                                                            kernel.truncation_px, kernel.huber_px),
                                 nullptr, params);
        if (level_prior)
        {
            // alignDirect minimises the MEAN edge cost plus the prior; Ceres the sum: scale the prior by n.
            const DirectPrior& pr = *level_prior;
            const Matrix6d information = (n * pr.weight * poseInformationDiagonal(pr.sigma_rad, pr.sigma_m)).asDiagonal();
            problem.AddResidualBlock(new PosePriorFactor(pr.T_world_cam, information), nullptr, params);
        }
        problem.SetManifold(params, &manifold);
        ceres::Solver::Options so;
        so.linear_solver_type = ceres::DENSE_QR;
        so.max_num_iterations = o.iterations_per_level;
        so.num_threads = 1;
        // Points outside the image or on the truncated field add a large constant to the cost: the default
        // relative tolerances would stop on the first small (relative) decrease.
        so.function_tolerance = 1e-10;
        so.gradient_tolerance = 1e-14;
        so.parameter_tolerance = 1e-10;
        so.logging_type = ceres::SILENT;
        ceres::Solver::Summary summary;
        ceres::Solve(so, &problem, &summary);
        st.iterations += int(summary.iterations.size()) - 1;
        any_step = any_step || summary.num_successful_steps > 0;
    };
    const int coarsest = int(field.levels.size()) - 1;
    for (int l = coarsest; l >= 0; --l) solveLevel(l, detail::pyramidRobustness(o), prior);
    if (any_step) T_world_cam = paramsToPose(params);
    st.final_edge_cost = edgeCost(o, field, 0, camera, model, T_world_cam, &st.final_inlier_ratio);
    st.ms = tic.Tac() * 1e3;
    if (stats) *stats = st;
    return any_step;
}

}  // namespace quasiloc::estimation
