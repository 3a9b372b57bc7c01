#pragma once
// Entropy-regularised optimal transport with a dustbin (SuperGlue-style partial assignment).
//
// Given a cost matrix C (M x N), build the augmented (M+1) x (N+1) cost with the last row and column at
// `dustbin_cost`, and find the plan P >= 0 minimising <P, C> - epsilon * H(P) subject to the marginals
//     sum_j P_ij = 1 for every real row i,   sum_j P_(M)j = N (dustbin row),
//     sum_i P_ij = 1 for every real column j, sum_i P_i(N) = M (dustbin column),
// so the total mass is M + N and P_ij (i < M, j < N) reads as the probability that i and j match. Entries
// that are not `allowed` (a geometric gate) carry no mass. Solved by Sinkhorn scaling in double precision
// (the kernel exp(-C/epsilon) stays representable for costs in [0, 2] and epsilon >= 0.01).
#include <Eigen/Core>

namespace quasiloc::frontend
{
using BoolMatrix = Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>;

struct SinkhornResult
{
    Eigen::MatrixXd plan;  ///< (M+1) x (N+1)
    int iterations = 0;
    double max_marginal_error = 0;  ///< largest |row sum - target| after the last column update
};

/** InputError for a non-finite cost, epsilon < 0.01, or an `allowed` mask of another size. M or N may be 0. */
SinkhornResult sinkhorn(const Eigen::MatrixXd& cost, double dustbin_cost, double epsilon, int max_iterations,
                        double tolerance, const BoolMatrix* allowed = nullptr);

}  // namespace quasiloc::frontend
