#include "marginalization.h"

#include <ceres/cost_function.h>

#include <Eigen/Cholesky>
#include <stdexcept>
#include <unordered_map>

namespace quasiloc::estimation::detail
{
namespace
{
using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/** The information of one point and its coupling to the dense blocks. */
struct PointBlock
{
    Eigen::MatrixXd H_pp;  // tangent x tangent
    Eigen::MatrixXd H_pd;  // tangent x dense dimension
};

/** Where each parameter block goes: a column offset in the dense part, or a point. */
class BlockIndex
{
   public:
    BlockIndex(ceres::Problem& problem, const std::vector<double*>& marginalize, const std::vector<double*>& points,
               const std::vector<double*>& keep)
    {
        const auto place = [&](double* b) {
            dense_[b] = dense_dim_;
            dense_dim_ += problem.ParameterBlockTangentSize(b);
        };
        for (double* b : marginalize) place(b);
        marginal_dim_ = dense_dim_;  // the marginalized blocks come first
        for (double* b : keep) place(b);
        for (size_t i = 0; i < points.size(); ++i) point_[points[i]] = int(i);
    }
    int denseDim() const { return dense_dim_; }
    int marginalDim() const { return marginal_dim_; }
    /** The dense column offset of b, or -1 when b is a point. */
    int denseOffset(double* b) const
    {
        const auto d = dense_.find(b);
        if (d != dense_.end()) return d->second;
        if (point_.count(b)) return -1;
        throw std::logic_error("marginalInformation: a residual block sees a parameter block no list names");
    }
    int pointIndex(double* b) const { return point_.at(b); }

   private:
    std::unordered_map<double*, int> dense_, point_;
    int dense_dim_ = 0, marginal_dim_ = 0;
};

/** Adds one residual block's J^T J (at the current values, losses applied) to H_dd and the points' blocks. */
void accumulate(ceres::Problem& problem, ceres::ResidualBlockId id, const BlockIndex& index, Eigen::MatrixXd& H_dd,
                std::vector<PointBlock>& points)
{
    std::vector<double*> params;
    problem.GetParameterBlocksForResidualBlock(id, &params);
    const int rows = problem.GetCostFunctionForResidualBlock(id)->num_residuals();
    std::vector<RowMajor> J(params.size());
    std::vector<double*> jac(params.size());
    std::vector<int> offset(params.size());
    int point = -1;
    for (size_t i = 0; i < params.size(); ++i)
    {
        J[i].resize(rows, problem.ParameterBlockTangentSize(params[i]));
        jac[i] = J[i].data();
        offset[i] = index.denseOffset(params[i]);
        if (offset[i] >= 0) continue;
        if (point >= 0) throw std::logic_error("marginalInformation: a residual block sees two points");
        point = int(i);
    }
    Eigen::VectorXd residuals(rows);
    double cost = 0;
    problem.EvaluateResidualBlock(id, true, &cost, residuals.data(), jac.data());
    for (size_t i = 0; i < params.size(); ++i)
    {
        if (int(i) == point) continue;
        for (size_t j = i; j < params.size(); ++j)
        {
            if (int(j) == point) continue;
            const Eigen::MatrixXd block = J[i].transpose() * J[j];
            H_dd.block(offset[i], offset[j], block.rows(), block.cols()) += block;
            if (j != i) H_dd.block(offset[j], offset[i], block.cols(), block.rows()) += block.transpose();
        }
    }
    if (point < 0) return;
    PointBlock& p = points[size_t(index.pointIndex(params[size_t(point)]))];
    const RowMajor& Jp = J[size_t(point)];
    if (p.H_pp.size() == 0)
    {
        p.H_pp = Eigen::MatrixXd::Zero(Jp.cols(), Jp.cols());
        p.H_pd = Eigen::MatrixXd::Zero(Jp.cols(), H_dd.cols());
    }
    p.H_pp.noalias() += Jp.transpose() * Jp;
    for (size_t i = 0; i < params.size(); ++i)
        if (int(i) != point) p.H_pd.middleCols(offset[i], J[i].cols()).noalias() += Jp.transpose() * J[i];
}
}  // namespace

Eigen::MatrixXd marginalInformation(ceres::Problem& problem, const std::vector<double*>& marginalize,
                                    const std::vector<double*>& points, const std::vector<double*>& keep,
                                    const std::vector<ceres::ResidualBlockId>& residual_blocks, double damping)
{
    const BlockIndex index(problem, marginalize, points, keep);
    const int n = index.denseDim(), m = index.marginalDim(), k = n - m;
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
    std::vector<PointBlock> point_blocks(points.size());
    for (ceres::ResidualBlockId id : residual_blocks) accumulate(problem, id, index, H, point_blocks);
    // Each point out on its own: H_dd -= H_dp (H_pp + damping)^-1 H_pd.
    for (const PointBlock& p : point_blocks)
    {
        if (p.H_pp.size() == 0) continue;  // seen by no residual of the subset: couples nothing
        Eigen::MatrixXd A = p.H_pp;
        A.diagonal().array() += damping;
        H.noalias() -= p.H_pd.transpose() * A.ldlt().solve(p.H_pd);
    }
    if (m == 0) return 0.5 * (H + H.transpose());
    Eigen::MatrixXd H_mm = H.topLeftCorner(m, m);
    H_mm.diagonal().array() += damping;
    const Eigen::MatrixXd H_mk = H.topRightCorner(m, k);
    const Eigen::MatrixXd out = H.bottomRightCorner(k, k) - H_mk.transpose() * H_mm.ldlt().solve(H_mk);
    return 0.5 * (out + out.transpose());
}
}  // namespace quasiloc::estimation::detail
