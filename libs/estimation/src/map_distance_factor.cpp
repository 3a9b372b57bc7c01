// MapDistanceCostFunction: stereo points against the map's distance field (map_distance_factor.h).
#include <quasiloc/core/error.h>
#include <quasiloc/estimation/map_distance_factor.h>
#include <quasiloc/estimation/pose_parametrization.h>

#include "parallel_points.h"

#include <algorithm>
#include <cmath>

namespace quasiloc::estimation
{
MapDistanceCostFunction::MapDistanceCostFunction(const map::DistanceField& field, std::vector<Eigen::Vector3d> p_cam,
                                                 std::vector<double> sigma_m, const Eigen::Isometry3d& T_body_cam,
                                                 double truncation_m, double huber_sigmas)
    : field_(field), truncation_m_(truncation_m), huber_(huber_sigmas)
{
    core::require(!p_cam.empty() && p_cam.size() == sigma_m.size(), "MapDistanceCostFunction",
                  "needs one sigma per point and at least one point");
    core::require(truncation_m > 0 && huber_sigmas > 0, "MapDistanceCostFunction", "truncation and Huber must be > 0");
    for (size_t i = 0; i < p_cam.size(); ++i)
    {
        core::require(sigma_m[i] > 0 && p_cam[i].allFinite(), "MapDistanceCostFunction",
                      "sigmas must be > 0 and points finite");
        p_body_.push_back(T_body_cam * p_cam[i]);
        inv_sigma_.push_back(1.0 / sigma_m[i]);
    }
    set_num_residuals(int(p_body_.size()));
    mutable_parameter_block_sizes()->push_back(kPoseSize);
}

bool MapDistanceCostFunction::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const
{
    const Eigen::Isometry3d T_map_body = paramsToPose(parameters[0]);
    double* J = jacobians ? jacobians[0] : nullptr;
    detail::forPointStripes(p_body_.size(),
                            [&](size_t begin, size_t end) { evaluatePoints(begin, end, T_map_body, residuals, J); });
    return true;
}

void MapDistanceCostFunction::evaluatePoints(size_t begin, size_t end, const Eigen::Isometry3d& T_map_body,
                                             double* residuals, double* J) const
{
    const Eigen::Matrix3d& R = T_map_body.linear();
    for (size_t i = begin; i < end; ++i)
    {
        double* Ji = J ? J + i * kPoseSize : nullptr;
        if (Ji) std::fill(Ji, Ji + kPoseSize, 0.0);
        const Eigen::Vector3d q = T_map_body * p_body_[i];
        Eigen::Vector3f g;
        const double d = std::min(double(field_.distance(q.cast<float>(), g)), truncation_m_);
        // sqrt(2 huber(x)) for x = d / sigma >= 0 (see direct_factor.h for why the Huber is inside).
        const double x = d * inv_sigma_[i];
        double slope = 1;
        if (x <= huber_)
            residuals[i] = x;
        else
        {
            residuals[i] = std::sqrt(2 * huber_ * x - huber_ * huber_);
            slope = huber_ / residuals[i];
        }
        if (!Ji || d >= truncation_m_) continue;
        // q' = R Exp(dtheta) p_body + t + R dp: dq/ddtheta = -R hat(p_body), dq/ddp = R.
        const Eigen::RowVector3d gr = g.cast<double>().transpose() * R;
        const Eigen::RowVector3d J_theta = -gr * hat(p_body_[i]);
        const double s = slope * inv_sigma_[i];
        for (int k = 0; k < 3; ++k) Ji[k] = s * J_theta[k], Ji[3 + k] = s * gr[k];
    }
}

}  // namespace quasiloc::estimation
