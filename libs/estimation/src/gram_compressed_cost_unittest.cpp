// GramCompressedCost against the cost function it wraps: the same cost, the same normal equations (J^T J, J^T r)
// on a pose manifold, and the same LM solution, on a many-row residual of one pose block.
#include <gtest/gtest.h>

#include <ceres/ceres.h>

#include <cstring>
#include <memory>
#include <quasiloc/core/error.h>
#include <quasiloc/estimation/pose_parametrization.h>
#include <random>

#include "gram_compressed_cost.h"

using namespace quasiloc::estimation;

namespace
{
/** Map points seen from a pose: residual i is the distance of the transformed point i to a plane through its true
 *  position (a stand-in for the window's surface term), with a saturation that makes it nonlinear. */
struct ManyRows
{
    std::vector<Eigen::Vector3d> p_body, p_map, n_map;
    template <typename T>
    bool operator()(T const* const* params, T* r) const
    {
        const T* pose = params[0];
        // The block's layout (pose_parametrization.h): quaternion x, y, z, w, then the translation.
        const Eigen::Quaternion<T> q(pose[3], pose[0], pose[1], pose[2]);
        const Eigen::Matrix<T, 3, 1> t(pose[4], pose[5], pose[6]);
        for (size_t i = 0; i < p_body.size(); ++i)
        {
            const Eigen::Matrix<T, 3, 1> p = q * p_body[i].cast<T>() + t;
            const T d = (p - p_map[i].cast<T>()).dot(n_map[i].cast<T>());
            r[i] = T(10) * d / (T(1) + T(0.5) * d * d);
        }
        return true;
    }
};

ManyRows scene(int n)
{
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    ManyRows s;
    for (int i = 0; i < n; ++i)
    {
        s.p_body.emplace_back(u(rng), u(rng), 2 + u(rng));
        s.p_map.push_back(s.p_body.back());  // truth: the identity pose
        s.n_map.push_back(Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized());
    }
    return s;
}

std::unique_ptr<ceres::CostFunction> manyRows(const ManyRows& s)
{
    auto* f = new ceres::DynamicAutoDiffCostFunction<ManyRows, 8>(new ManyRows(s));
    f->AddParameterBlock(kPoseSize);
    f->SetNumResiduals(int(s.p_body.size()));
    return std::unique_ptr<ceres::CostFunction>(f);
}

/** The pose block's layout with a manifold whose Jacobians are the true derivatives of Plus: autodiff's ambient
 *  Jacobian applies (the project's PoseManifold lifts a tangent Jacobian instead, pose_parametrization.h). */
using QuaternionThenTranslation = ceres::ProductManifold<ceres::EigenQuaternionManifold, ceres::EuclideanManifold<3>>;

void perturbedPose(double* pose)
{
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translate(Eigen::Vector3d(0.05, -0.03, 0.02));
    T.rotate(Eigen::AngleAxisd(0.04, Eigen::Vector3d(0.3, 1, -0.2).normalized()));
    poseToParams(T, pose);
}
}  // namespace

TEST(GramCompressedCost, SameCostAndNormalEquationsOnTheManifold)
{
    const ManyRows s = scene(500);
    double pose[kPoseSize];
    perturbedPose(pose);
    QuaternionThenTranslation manifold;
    ceres::Problem::Options po;
    po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem full(po), compressed(po);
    double pose_c[kPoseSize];
    std::copy(pose, pose + kPoseSize, pose_c);
    full.AddParameterBlock(pose, kPoseSize, &manifold);
    compressed.AddParameterBlock(pose_c, kPoseSize, &manifold);
    const auto id_full = full.AddResidualBlock(manyRows(s).release(), nullptr, pose);
    const auto id_c = compressed.AddResidualBlock(new detail::GramCompressedCost(manyRows(s)), nullptr, pose_c);
    EXPECT_EQ(compressed.GetCostFunctionForResidualBlock(id_c)->num_residuals(), kPoseSize + 1);

    std::vector<double> r_full(500), J_full(500 * 6), r_c(8), J_c(8 * 6);
    double cost_full = 0, cost_c = 0;
    double* jf[1] = {J_full.data()};
    double* jc[1] = {J_c.data()};
    full.EvaluateResidualBlock(id_full, false, &cost_full, r_full.data(), jf);
    compressed.EvaluateResidualBlock(id_c, false, &cost_c, r_c.data(), jc);
    using RowMajor = Eigen::Matrix<double, -1, -1, Eigen::RowMajor>;
    const Eigen::Map<RowMajor> Jf(J_full.data(), 500, 6), Jc(J_c.data(), 8, 6);
    const Eigen::Map<Eigen::VectorXd> rf(r_full.data(), 500), rc(r_c.data(), 8);
    EXPECT_GT(cost_full, 1.0);
    EXPECT_NEAR(cost_c, cost_full, 1e-10 * cost_full);
    const Eigen::MatrixXd H_full = Jf.transpose() * Jf, H_c = Jc.transpose() * Jc;
    EXPECT_LT((H_c - H_full).norm(), 1e-10 * H_full.norm());
    const Eigen::VectorXd g_full = Jf.transpose() * rf, g_c = Jc.transpose() * rc;
    EXPECT_LT((g_c - g_full).norm(), 1e-10 * g_full.norm());
    // Residuals only (an LM trial step): the same cost.
    double cost_trial = 0;
    compressed.EvaluateResidualBlock(id_c, false, &cost_trial, r_c.data(), nullptr);
    EXPECT_NEAR(cost_trial, cost_full, 1e-10 * cost_full);
}

TEST(GramCompressedCost, TheSolverTakesTheSameSteps)
{
    const ManyRows s = scene(300);
    QuaternionThenTranslation manifold;
    double pose_full[kPoseSize], pose_c[kPoseSize];
    perturbedPose(pose_full);
    perturbedPose(pose_c);
    ceres::Problem::Options po;
    po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem full(po), compressed(po);
    full.AddParameterBlock(pose_full, kPoseSize, &manifold);
    compressed.AddParameterBlock(pose_c, kPoseSize, &manifold);
    full.AddResidualBlock(manyRows(s).release(), nullptr, pose_full);
    compressed.AddResidualBlock(new detail::GramCompressedCost(manyRows(s)), nullptr, pose_c);
    ceres::Solver::Options so;
    so.max_num_iterations = 3;  // not converged: the intermediate steps themselves must agree
    so.linear_solver_type = ceres::DENSE_QR;
    so.logging_type = ceres::SILENT;
    ceres::Solver::Summary a, b;
    ceres::Solve(so, &full, &a);
    ceres::Solve(so, &compressed, &b);
    ASSERT_EQ(a.iterations.size(), b.iterations.size());
    for (size_t i = 0; i < a.iterations.size(); ++i)
        EXPECT_NEAR(b.iterations[i].cost, a.iterations[i].cost, 1e-9 * a.iterations[0].cost) << "iteration " << i;
    for (int k = 0; k < kPoseSize; ++k) EXPECT_NEAR(pose_c[k], pose_full[k], 1e-9);
    EXPECT_LT(a.final_cost, 1e-3 * a.initial_cost);  // it did move towards the truth
}

TEST(GramCompressedCost, RefusesSeveralParameterBlocks)
{
    auto* f = new ceres::DynamicAutoDiffCostFunction<ManyRows, 8>(new ManyRows(scene(3)));
    f->AddParameterBlock(kPoseSize);
    f->AddParameterBlock(3);
    f->SetNumResiduals(3);
    EXPECT_THROW(detail::GramCompressedCost(std::unique_ptr<ceres::CostFunction>(f)), quasiloc::core::InputError);
}

namespace
{
/** Counts the calls that reach the wrapped function, with and without Jacobians. */
class CountingCost final : public ceres::CostFunction
{
   public:
    CountingCost(std::unique_ptr<ceres::CostFunction> inner, int& with_jacobians, int& without)
        : inner_(std::move(inner)), with_(with_jacobians), without_(without)
    {
        set_num_residuals(inner_->num_residuals());
        *mutable_parameter_block_sizes() = inner_->parameter_block_sizes();
    }
    bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override
    {
        ++(jacobians && jacobians[0] ? with_ : without_);
        return inner_->Evaluate(parameters, residuals, jacobians);
    }

   private:
    std::unique_ptr<ceres::CostFunction> inner_;
    int &with_, &without_;
};
}  // namespace

// The window's marginal evaluates the Jacobians where Ceres's last accepted step already did: the kept evaluation
// is returned, bit for bit; another point, or an evaluation without Jacobians, reaches the wrapped function.
TEST(GramCompressedCost, AnotherEvaluationWithJacobiansAtTheSamePointIsTheKeptOne)
{
    int with = 0, without = 0;
    const detail::GramCompressedCost f(std::make_unique<CountingCost>(manyRows(scene(300)), with, without));
    double pose[kPoseSize];
    perturbedPose(pose);
    const double* params[1] = {pose};
    constexpr int kOut = kPoseSize + 1;
    double r1[kOut], J1[kOut * kPoseSize], r2[kOut], J2[kOut * kPoseSize];
    double* jac1[1] = {J1};
    double* jac2[1] = {J2};
    ASSERT_TRUE(f.Evaluate(params, r1, jac1));
    ASSERT_TRUE(f.Evaluate(params, r2, jac2));
    EXPECT_EQ(with, 1);
    EXPECT_EQ(0, std::memcmp(r1, r2, sizeof r1));
    EXPECT_EQ(0, std::memcmp(J1, J2, sizeof J1));

    double cost_only[kOut];
    ASSERT_TRUE(f.Evaluate(params, cost_only, nullptr));
    EXPECT_EQ(without, 1);
    EXPECT_NEAR(cost_only[0], Eigen::Map<Eigen::VectorXd>(r1, kOut).norm(), 1e-9 * cost_only[0]);

    pose[4] += 1e-9;  // another point: evaluated again, and kept in place of the first
    ASSERT_TRUE(f.Evaluate(params, r2, jac2));
    EXPECT_EQ(with, 2);
    EXPECT_NE(0, std::memcmp(r1, r2, sizeof r1));
    pose[4] -= 1e-9;
    ASSERT_TRUE(f.Evaluate(params, r2, jac2));
    EXPECT_EQ(with, 3);
}
