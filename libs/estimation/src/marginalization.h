#pragma once
// Marginal information of some parameter blocks of a Ceres problem, from the Jacobian of a subset of its
// residual blocks at the current parameter values (tangent space; robust losses applied).
#include <ceres/problem.h>

#include <Eigen/Core>
#include <vector>

namespace quasiloc::estimation::detail
{
/** H_kk - H_km H_mm^-1 H_mk where k = `keep` (in this order) and m = `marginalize`; `damping` is added to
 *  the diagonal of H_mm (blocks a subset does not see would make it singular). */
Eigen::MatrixXd marginalInformation(ceres::Problem& problem, const std::vector<double*>& marginalize,
                                    const std::vector<double*>& keep,
                                    const std::vector<ceres::ResidualBlockId>& residual_blocks, double damping);
}  // namespace quasiloc::estimation::detail
