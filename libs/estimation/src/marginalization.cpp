#include "marginalization.h"

#include <ceres/crs_matrix.h>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

namespace quasiloc::estimation::detail
{
Eigen::MatrixXd marginalInformation(ceres::Problem& problem, const std::vector<double*>& marginalize,
                                    const std::vector<double*>& keep,
                                    const std::vector<ceres::ResidualBlockId>& residual_blocks, double damping)
{
    ceres::Problem::EvaluateOptions eo;
    eo.parameter_blocks = marginalize;
    eo.parameter_blocks.insert(eo.parameter_blocks.end(), keep.begin(), keep.end());
    eo.residual_blocks = residual_blocks;
    eo.apply_loss_function = true;
    eo.num_threads = 1;
    int keep_dim = 0;
    for (double* b : keep) keep_dim += problem.ParameterBlockTangentSize(b);
    if (residual_blocks.empty()) return Eigen::MatrixXd::Zero(keep_dim, keep_dim);

    ceres::CRSMatrix crs;
    double cost = 0;
    problem.Evaluate(eo, &cost, nullptr, nullptr, &crs);
    std::vector<Eigen::Triplet<double>> trip;
    trip.reserve(crs.values.size());
    for (int r = 0; r < crs.num_rows; ++r)
        for (int k = crs.rows[r]; k < crs.rows[r + 1]; ++k) trip.emplace_back(r, crs.cols[k], crs.values[k]);
    Eigen::SparseMatrix<double> J(crs.num_rows, crs.num_cols);
    J.setFromTriplets(trip.begin(), trip.end());
    const Eigen::SparseMatrix<double> H = (J.transpose() * J).pruned();
    const int n = crs.num_cols, m = n - keep_dim;
    const Eigen::MatrixXd H_kk = Eigen::MatrixXd(H.bottomRightCorner(keep_dim, keep_dim));
    if (m == 0) return H_kk;

    Eigen::SparseMatrix<double> H_mm = H.topLeftCorner(m, m);
    for (int i = 0; i < m; ++i) H_mm.coeffRef(i, i) += damping;
    const Eigen::MatrixXd H_mk = Eigen::MatrixXd(H.topRightCorner(m, keep_dim));
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(H_mm);
    const Eigen::MatrixXd X = ldlt.solve(H_mk);
    Eigen::MatrixXd out = H_kk - H_mk.transpose() * X;
    return 0.5 * (out + out.transpose());
}
}  // namespace quasiloc::estimation::detail
