// The window's marginalisation, built block by block with its landmarks eliminated one at a time, against the
// textbook Schur complement of the whole problem's dense J^T J (Ceres's own Jacobian, tangent space, losses
// applied), on a problem shaped like the window: two poses on the pose manifold, two speed-bias blocks, landmarks
// seen from both poses, a robust loss, and blocks left out of the residual subset.
#include <gtest/gtest.h>

#include <ceres/ceres.h>
#include <ceres/crs_matrix.h>

#include <Eigen/Cholesky>
#include <quasiloc/estimation/pose_parametrization.h>
#include <random>
#include <stdexcept>

#include "marginalization.h"

using namespace quasiloc::estimation;

namespace
{
/** A nonlinear residual between a pose (translation and quaternion), a 9-vector and an optional point. */
struct Coupling
{
    explicit Coupling(double w) : w(w) {}
    template <typename T>
    bool operator()(const T* pose, const T* sb, const T* point, T* r) const
    {
        for (int i = 0; i < 3; ++i)
            r[i] = T(w) * (pose[i] * point[(i + 1) % 3] + sin(pose[3 + i]) + sb[i] * sb[3 + i] - point[i] + sb[6 + i]);
        return true;
    }
    double w;
};

struct PoseToPose
{
    template <typename T>
    bool operator()(const T* a, const T* b, T* r) const
    {
        for (int i = 0; i < 7; ++i) r[i] = a[i] * a[(i + 1) % 7] - b[i] + T(0.3) * b[(i + 2) % 7] * b[(i + 2) % 7];
        return true;
    }
};

struct TwoPoints
{
    template <typename T>
    bool operator()(const T* p, const T* q, T* r) const
    {
        for (int i = 0; i < 3; ++i) r[i] = p[i] - q[i];
        return true;
    }
};

struct Problem
{
    double pose[2][kPoseSize];
    double sb[2][kSpeedBiasSize];
    double points[5][3];
    PoseManifold manifold;
    ceres::Problem problem;
    std::vector<ceres::ResidualBlockId> subset;

    Problem()
        : problem([] {
              ceres::Problem::Options o;
              o.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
              return o;
          }())
    {
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> u(-1, 1);
        for (auto& p : pose)
        {
            Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
            T.translate(Eigen::Vector3d(u(rng), u(rng), u(rng)));
            T.rotate(Eigen::AngleAxisd(u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized()));
            poseToParams(T, p);
            problem.AddParameterBlock(p, kPoseSize, &manifold);
        }
        for (auto& s : sb)
            for (double& v : s) v = u(rng);
        for (auto& p : points)
            for (double& v : p) v = u(rng);
        for (int f = 0; f < 2; ++f)
            for (int k = 0; k < 5; ++k)
            {
                auto* c = new ceres::AutoDiffCostFunction<Coupling, 3, kPoseSize, kSpeedBiasSize, 3>(
                    new Coupling(1.0 + 0.1 * k));
                // A Huber on some of them, in its robust part: the marginal must see the loss.
                ceres::LossFunction* loss = k % 2 ? new ceres::HuberLoss(0.05) : nullptr;
                subset.push_back(problem.AddResidualBlock(c, loss, pose[f], sb[f], points[k]));
            }
        subset.push_back(problem.AddResidualBlock(
            new ceres::AutoDiffCostFunction<PoseToPose, 7, kPoseSize, kPoseSize>(new PoseToPose), nullptr, pose[0],
            pose[1]));
        // Outside the subset: must not count.
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PoseToPose, 7, kPoseSize, kPoseSize>(new PoseToPose),
                                 nullptr, pose[1], pose[0]);
    }
};

/** The textbook marginal: the dense J^T J of the subset, marginalized and points eliminated together. */
Eigen::MatrixXd denseReference(Problem& p, const std::vector<double*>& marg, const std::vector<double*>& keep,
                               double damping)
{
    ceres::Problem::EvaluateOptions eo;
    eo.parameter_blocks = marg;
    eo.parameter_blocks.insert(eo.parameter_blocks.end(), keep.begin(), keep.end());
    eo.residual_blocks = p.subset;
    eo.apply_loss_function = true;
    ceres::CRSMatrix crs;
    double cost = 0;
    p.problem.Evaluate(eo, &cost, nullptr, nullptr, &crs);
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
    for (int r = 0; r < crs.num_rows; ++r)
        for (int k = crs.rows[size_t(r)]; k < crs.rows[size_t(r) + 1]; ++k)
            J(r, crs.cols[size_t(k)]) = crs.values[size_t(k)];
    const Eigen::MatrixXd H = J.transpose() * J;
    int keep_dim = 0;
    for (double* b : keep) keep_dim += p.problem.ParameterBlockTangentSize(b);
    const int m = int(H.rows()) - keep_dim;
    Eigen::MatrixXd H_mm = H.topLeftCorner(m, m);
    H_mm.diagonal().array() += damping;
    const Eigen::MatrixXd H_mk = H.topRightCorner(m, keep_dim);
    return H.bottomRightCorner(keep_dim, keep_dim) - H_mk.transpose() * H_mm.ldlt().solve(H_mk);
}

std::vector<double*> pointBlocks(Problem& p)
{
    std::vector<double*> out;
    for (auto& q : p.points) out.push_back(q);
    return out;
}
}  // namespace

TEST(Marginalization, BlockwiseEqualsTheDenseSchurComplement)
{
    Problem p;
    const std::vector<double*> marg = {p.pose[0], p.sb[0]}, keep = {p.pose[1], p.sb[1]};
    std::vector<double*> all_marg = marg;
    for (double* q : pointBlocks(p)) all_marg.push_back(q);
    for (double damping : {1e-6, 1e-2})
    {
        const Eigen::MatrixXd reference = denseReference(p, all_marg, keep, damping);
        const Eigen::MatrixXd H = detail::marginalInformation(p.problem, marg, pointBlocks(p), keep, p.subset, damping);
        ASSERT_EQ(H.rows(), 15);
        ASSERT_EQ(H.cols(), 15);
        EXPECT_LT((H - reference).norm(), 1e-9 * reference.norm()) << "damping " << damping;
        EXPECT_GT(reference.norm(), 1.0);  // a marginal with content, not two zeros that agree
    }
}

TEST(Marginalization, KeepsOnlyThePoseWithNothingDenseToMarginalize)
{
    Problem p;
    const std::vector<double*> keep = {p.pose[0], p.sb[0], p.pose[1], p.sb[1]};
    const Eigen::MatrixXd reference = denseReference(p, pointBlocks(p), keep, 1e-6);
    const Eigen::MatrixXd H = detail::marginalInformation(p.problem, {}, pointBlocks(p), keep, p.subset, 1e-6);
    EXPECT_LT((H - reference).norm(), 1e-9 * reference.norm());
}

TEST(Marginalization, RefusesAResidualOnTwoPointsOrAnUnnamedBlock)
{
    Problem p;
    const std::vector<double*> marg = {p.pose[0], p.sb[0]}, keep = {p.pose[1], p.sb[1]};
    std::vector<ceres::ResidualBlockId> subset = p.subset;
    subset.push_back(p.problem.AddResidualBlock(new ceres::AutoDiffCostFunction<TwoPoints, 3, 3, 3>(new TwoPoints),
                                                nullptr, p.points[0], p.points[1]));
    EXPECT_THROW(detail::marginalInformation(p.problem, marg, pointBlocks(p), keep, subset, 1e-6), std::logic_error);
    EXPECT_THROW(detail::marginalInformation(p.problem, marg, {}, keep, p.subset, 1e-6), std::logic_error);
}
