#pragma once
// Marginal information of some parameter blocks of a Ceres problem, from the Jacobian of a subset of its
// residual blocks at the current parameter values (tangent space; robust losses applied).
#include <ceres/problem.h>

#include <Eigen/Core>
#include <vector>

namespace quasiloc::estimation::detail
{
/** H_kk - H_km H_mm^-1 H_mk where k = `keep` (in this order) and m = `marginalize` and `points`; `damping` is added
 *  to the diagonal of H_mm (blocks a subset does not see would make it singular).
 *
 *  `points` are the landmark-like blocks: no residual block may see two of them. Each is eliminated on its own
 *  (its 3 x 3 block, a Schur complement per point), the rest densely: the window's H is a few dozen dense
 *  dimensions plus one small block per landmark, and building it block by block avoids the sparse Jacobian of
 *  thousands of rows a general sparse path would assemble. Throws std::logic_error when a residual block sees a
 *  parameter block none of the lists names, or two points. */
Eigen::MatrixXd marginalInformation(ceres::Problem& problem, const std::vector<double*>& marginalize,
                                    const std::vector<double*>& points, const std::vector<double*>& keep,
                                    const std::vector<ceres::ResidualBlockId>& residual_blocks, double damping);
}  // namespace quasiloc::estimation::detail
