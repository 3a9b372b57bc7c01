#include "gram_compressed_cost.h"

#include "scratch.h"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstring>
#include <quasiloc/core/error.h>
#include <vector>

namespace quasiloc::estimation::detail
{
GramCompressedCost::GramCompressedCost(std::unique_ptr<ceres::CostFunction> inner) : inner_(std::move(inner))
{
    core::require(inner_ && inner_->parameter_block_sizes().size() == 1 && inner_->num_residuals() > 0,
                  "GramCompressedCost", "needs a cost function with one parameter block and residuals");
    params_ = inner_->parameter_block_sizes()[0];
    set_num_residuals(params_ + 1);
    mutable_parameter_block_sizes()->push_back(params_);
}

bool GramCompressedCost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const
{
    const bool want_jacobian = jacobians && jacobians[0];
    if (want_jacobian)
    {
        const std::lock_guard<std::mutex> lock(last_mutex_);
        // Bit for bit: the inner function sees exactly what it saw then.
        if (!last_.parameters.empty() &&
            std::memcmp(last_.parameters.data(), parameters[0], last_.parameters.size() * sizeof(double)) == 0)
        {
            std::copy(last_.residuals.begin(), last_.residuals.end(), residuals);
            std::copy(last_.jacobian.begin(), last_.jacobian.end(), jacobians[0]);
            return true;
        }
    }
    return evaluateInner(parameters[0], residuals, want_jacobian ? jacobians[0] : nullptr);
}

bool GramCompressedCost::evaluateInner(const double* parameters, double* residuals, double* jacobian) const
{
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    const int n = inner_->num_residuals(), p = params_;
    // Reused per thread: the window evaluates its blocks on one thread, thousands of rows each time. The inner
    // function writes every row.
    thread_local std::vector<double> r, J;
    growScratch(r, size_t(n));
    double* inner_jacobians[1] = {nullptr};
    if (jacobian)
    {
        growScratch(J, size_t(n) * size_t(p));
        inner_jacobians[0] = J.data();
    }
    const double* inner_parameters[1] = {parameters};
    if (!inner_->Evaluate(inner_parameters, r.data(), jacobian ? inner_jacobians : nullptr)) return false;
    const Eigen::Map<const Eigen::VectorXd> rv(r.data(), n);
    Eigen::Map<Eigen::VectorXd> out(residuals, p + 1);
    if (!jacobian)
    {
        out.setZero();
        out[0] = rv.norm();
        return true;
    }
    const Eigen::Map<const RowMajor> Jm(J.data(), n, p);
    Eigen::MatrixXd G(p + 1, p + 1);
    G.topLeftCorner(p, p).noalias() = Jm.transpose() * Jm;
    G.topRightCorner(p, 1).noalias() = Jm.transpose() * rv;
    G.bottomLeftCorner(1, p) = G.topRightCorner(p, 1).transpose();
    G(p, p) = rv.squaredNorm();
    // G = V D V^T = R^T R with R = D^1/2 V^T: semi-definite G (a pose block's ambient Jacobian has rank 6 of 7)
    // factors without the pivoting a Cholesky would need.
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(G);
    const Eigen::VectorXd d = es.eigenvalues().cwiseMax(0.0).cwiseSqrt();
    const Eigen::MatrixXd R = d.asDiagonal() * es.eigenvectors().transpose();
    out = R.col(p);
    Eigen::Map<RowMajor>(jacobian, p + 1, p) = R.leftCols(p);
    const std::lock_guard<std::mutex> lock(last_mutex_);
    last_.parameters.assign(parameters, parameters + p);
    last_.residuals.assign(residuals, residuals + p + 1);
    last_.jacobian.assign(jacobian, jacobian + size_t(p + 1) * size_t(p));
    return true;
}
}  // namespace quasiloc::estimation::detail
