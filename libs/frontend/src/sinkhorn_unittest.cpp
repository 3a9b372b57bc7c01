// Sinkhorn with a dustbin: the marginals of sinkhorn.h hold, the gate removes mass, a clear assignment
// is recovered.
#include <gtest/gtest.h>

#include <quasiloc/core/error.h>
#include <quasiloc/frontend/sinkhorn.h>
#include <random>

using namespace quasiloc::frontend;

namespace
{
void expectMarginals(const Eigen::MatrixXd& P, int M, int N, double tol)
{
    ASSERT_EQ(P.rows(), M + 1);
    ASSERT_EQ(P.cols(), N + 1);
    EXPECT_GE(P.minCoeff(), 0.0);
    for (int i = 0; i < M; ++i) EXPECT_NEAR(P.row(i).sum(), 1.0, tol) << "row " << i;
    for (int j = 0; j < N; ++j) EXPECT_NEAR(P.col(j).sum(), 1.0, tol) << "column " << j;
    EXPECT_NEAR(P.row(M).sum(), double(N), tol * std::max(1, N));
    EXPECT_NEAR(P.col(N).sum(), double(M), tol * std::max(1, M));
    EXPECT_NEAR(P.sum(), double(M + N), tol * (M + N));
}
}  // namespace

TEST(Sinkhorn, MarginalsHoldForRandomCosts)
{
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.0, 2.0);
    for (auto [M, N] : {std::pair{20, 30}, std::pair{30, 20}, std::pair{1, 5}, std::pair{7, 7}})
    {
        Eigen::MatrixXd C(M, N);
        for (int i = 0; i < M; ++i)
            for (int j = 0; j < N; ++j) C(i, j) = u(rng);
        const SinkhornResult r = sinkhorn(C, 0.5, 0.05, 2000, 1e-9);
        EXPECT_LT(r.max_marginal_error, 1e-9);
        expectMarginals(r.plan, M, N, 1e-8);
    }
}

TEST(Sinkhorn, GatedEntriesCarryNoMass)
{
    const int M = 6, N = 8;
    Eigen::MatrixXd C = Eigen::MatrixXd::Constant(M, N, 0.2);
    BoolMatrix allowed = BoolMatrix::Constant(M, N, true);
    allowed.row(2).setConstant(false);
    allowed(0, 0) = false;
    const SinkhornResult r = sinkhorn(C, 0.6, 0.05, 2000, 1e-10, &allowed);
    expectMarginals(r.plan, M, N, 1e-8);
    EXPECT_EQ(r.plan(0, 0), 0.0);
    EXPECT_EQ(r.plan.row(2).head(N).sum(), 0.0);
    EXPECT_NEAR(r.plan(2, N), 1.0, 1e-8);  // a fully gated row goes to the dustbin
}

TEST(Sinkhorn, RecoversAPermutationAndSendsUnmatchedToTheDustbin)
{
    // Rows 0..4 match columns perm[i] at cost 0.05; row 5 and column 5 match nothing (cost 1 everywhere).
    const int perm[5] = {3, 0, 4, 1, 2};
    Eigen::MatrixXd C = Eigen::MatrixXd::Constant(6, 6, 1.0);
    for (int i = 0; i < 5; ++i) C(i, perm[i]) = 0.05;
    const SinkhornResult r = sinkhorn(C, 0.4, 0.05, 500, 1e-9);
    for (int i = 0; i < 5; ++i)
    {
        int j = -1;
        r.plan.row(i).maxCoeff(&j);
        EXPECT_EQ(j, perm[i]);
        EXPECT_GT(r.plan(i, perm[i]), 0.9);
    }
    int j5 = -1;
    r.plan.row(5).maxCoeff(&j5);
    EXPECT_EQ(j5, 6);  // dustbin column
}

TEST(Sinkhorn, EmptySidesAndBadInput)
{
    const SinkhornResult r = sinkhorn(Eigen::MatrixXd(0, 4), 0.5, 0.05, 100, 1e-9);
    expectMarginals(r.plan, 0, 4, 1e-9);
    EXPECT_THROW(sinkhorn(Eigen::MatrixXd::Zero(2, 2), 0.5, 0.001, 100, 1e-9), quasiloc::core::InputError);
    Eigen::MatrixXd bad = Eigen::MatrixXd::Zero(2, 2);
    bad(1, 1) = std::nan("");
    EXPECT_THROW(sinkhorn(bad, 0.5, 0.05, 100, 1e-9), quasiloc::core::InputError);
}
