#pragma once
// A residual block of many rows on one parameter block, handed to Ceres as a few rows with the same normal
// equations: for the window's edge term and stereo-to-surface term (thousands of rows, one pose each).
#include <ceres/cost_function.h>

#include <memory>
#include <mutex>
#include <vector>

namespace quasiloc::estimation::detail
{
/** Wraps a cost function of one parameter block (ambient size p) and n residuals into p + 1 residuals r', J' with
 *  J'^T J' = J^T J, J'^T r' = J^T r and |r'| = |r| (the Gram matrix of [J r] factored as R^T R; r' and J' are the
 *  columns of R). Every Gauss-Newton or LM step, every cost and every marginal taken from it is the inner
 *  function's, up to rounding; what changes is Ceres's own work per row (the manifold's Jacobian product, the
 *  validity checks, the Schur elimination's outer products), now per 8 rows instead of per thousands. A residual
 *  evaluation without Jacobians (the LM's trial steps) returns (|r|, 0, ..., 0).
 *
 *  The last evaluation with Jacobians is kept: another one at the same parameter values returns it without
 *  calling the inner function (an evaluation without Jacobians always calls it). Ceres evaluates the Jacobians at
 *  every accepted step, the last one included, and the window's marginal evaluates them again at that same point:
 *  the second costs a copy. */
class GramCompressedCost final : public ceres::CostFunction
{
   public:
    explicit GramCompressedCost(std::unique_ptr<ceres::CostFunction> inner);
    bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

   private:
    /** The output of the last evaluation with Jacobians, at `parameters`. */
    struct Evaluation
    {
        std::vector<double> parameters, residuals, jacobian;
    };
    bool evaluateInner(const double* parameters, double* residuals, double* jacobian) const;

    std::unique_ptr<ceres::CostFunction> inner_;
    int params_ = 0;
    mutable std::mutex last_mutex_;  // Ceres may evaluate blocks on several threads; one block never twice at once
    mutable Evaluation last_;
};
}  // namespace quasiloc::estimation::detail
