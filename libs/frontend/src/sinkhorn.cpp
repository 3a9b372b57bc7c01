#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/frontend/sinkhorn.h>

namespace quasiloc::frontend
{
SinkhornResult sinkhorn(const Eigen::MatrixXd& cost, double dustbin_cost, double epsilon, int max_iterations,
                        double tolerance, const BoolMatrix* allowed)
{
    core::require(epsilon >= 0.01 && std::isfinite(epsilon), "sinkhorn", "epsilon must be finite and >= 0.01");
    core::require(cost.allFinite() && std::isfinite(dustbin_cost), "sinkhorn",
                  "the cost matrix has a non-finite value");
    core::require(!allowed || (allowed->rows() == cost.rows() && allowed->cols() == cost.cols()), "sinkhorn",
                  "the allowed mask has another size than the cost matrix");
    const int M = int(cost.rows()), N = int(cost.cols());
    Eigen::MatrixXd K(M + 1, N + 1);
    // Costs relative to the smallest one keep the kernel away from underflow whatever the offset of C.
    const double c0 = std::min(M && N ? cost.minCoeff() : dustbin_cost, dustbin_cost);
    K.topLeftCorner(M, N) = (-(cost.array() - c0) / epsilon).exp().matrix();
    if (allowed)
        for (int i = 0; i < M; ++i)
            for (int j = 0; j < N; ++j)
                if (!(*allowed)(i, j)) K(i, j) = 0;
    K.col(N).setConstant(std::exp(-(dustbin_cost - c0) / epsilon));
    K.row(M).setConstant(std::exp(-(dustbin_cost - c0) / epsilon));

    Eigen::VectorXd a = Eigen::VectorXd::Ones(M + 1), b = Eigen::VectorXd::Ones(N + 1);
    a(M) = N, b(N) = M;
    Eigen::VectorXd u = Eigen::VectorXd::Ones(M + 1), v = Eigen::VectorXd::Ones(N + 1);
    SinkhornResult r;
    for (r.iterations = 0; r.iterations < max_iterations;)
    {
        u = a.cwiseQuotient(K * v);
        v = b.cwiseQuotient(K.transpose() * u);
        ++r.iterations;
        // Columns hold exactly after the v update; the rows tell how far from convergence we are.
        r.max_marginal_error = (u.cwiseProduct(K * v) - a).cwiseAbs().maxCoeff();
        if (r.max_marginal_error < tolerance) break;
    }
    r.plan = u.asDiagonal() * K * v.asDiagonal();
    return r;
}
}  // namespace quasiloc::frontend
