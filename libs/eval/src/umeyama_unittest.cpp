#include <gtest/gtest.h>

#include <quasiloc/core/error.h>
#include <quasiloc/eval/umeyama.h>
#include <random>

using quasiloc::eval::umeyamaAlignment;

namespace
{
Eigen::Matrix3Xd randomPoints(std::mt19937& rng, int n)
{
    std::uniform_real_distribution<double> u(-5, 5);
    Eigen::Matrix3Xd P(3, n);
    for (int i = 0; i < n; ++i) P.col(i) = Eigen::Vector3d(u(rng), u(rng), u(rng));
    return P;
}

Eigen::Matrix3d randomRotation(std::mt19937& rng)
{
    std::normal_distribution<double> g;
    return Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
}
}  // namespace

TEST(Umeyama, RecoversRandomSE3)
{
    std::mt19937 rng(42);
    for (int trial = 0; trial < 20; ++trial)
    {
        const Eigen::Matrix3d R = randomRotation(rng);
        const Eigen::Vector3d t = 10 * Eigen::Vector3d::Random();
        const Eigen::Matrix3Xd src = randomPoints(rng, 30);
        const Eigen::Matrix3Xd dst = (R * src).colwise() + t;
        const auto S = umeyamaAlignment(src, dst, false);
        EXPECT_LT((S.R - R).norm(), 1e-10);
        EXPECT_LT((S.t - t).norm(), 1e-9);
        EXPECT_EQ(S.scale, 1.0);
        EXPECT_FALSE(S.degenerate);
    }
}

TEST(Umeyama, RecoversRandomSim3)
{
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> scale(0.2, 5.0);
    for (int trial = 0; trial < 20; ++trial)
    {
        const Eigen::Matrix3d R = randomRotation(rng);
        const Eigen::Vector3d t = 10 * Eigen::Vector3d::Random();
        const double s = scale(rng);
        const Eigen::Matrix3Xd src = randomPoints(rng, 12);
        const Eigen::Matrix3Xd dst = (s * R * src).colwise() + t;
        const auto S = umeyamaAlignment(src, dst, true);
        EXPECT_NEAR(S.scale, s, 1e-10);
        EXPECT_LT((S.R - R).norm(), 1e-10);
        EXPECT_LT((S.t - t).norm(), 1e-9);
        EXPECT_LT((S.matrix().topLeftCorner<3, 3>() - s * R).norm(), 1e-9);
        // With scale fixed to 1 the fit cannot be exact.
        const auto rigid = umeyamaAlignment(src, dst, false);
        const double rigid_residual = ((rigid.R * src).colwise() + rigid.t - dst).norm();
        if (std::abs(s - 1) > 0.1)
        {
            EXPECT_GT(rigid_residual, 1e-3);
        }
    }
}

TEST(Umeyama, MirroredPointsStillGiveAProperRotation)
{
    std::mt19937 rng(5);
    const Eigen::Matrix3Xd src = randomPoints(rng, 10);
    Eigen::Matrix3Xd dst = src;
    dst.row(0) *= -1;  // a reflection: the unconstrained SVD solution would have det = -1
    const auto S = umeyamaAlignment(src, dst, false);
    EXPECT_NEAR(S.R.determinant(), 1.0, 1e-12);
    EXPECT_NEAR((S.R * S.R.transpose() - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12);
}

TEST(Umeyama, DegenerateAndBadInput)
{
    Eigen::Matrix3Xd line(3, 5);
    for (int i = 0; i < 5; ++i) line.col(i) = Eigen::Vector3d(i, 2.0 * i, 0.5 * i);
    const Eigen::Matrix3Xd moved = line.colwise() + Eigen::Vector3d(1, 2, 3);
    const auto S = umeyamaAlignment(line, moved, false);
    EXPECT_TRUE(S.degenerate);
    EXPECT_LT((S.apply(line.col(4)) - moved.col(4)).norm(), 1e-9);  // still a minimiser
    EXPECT_THROW(umeyamaAlignment(line, moved.leftCols(3), false), quasiloc::core::InputError);
    EXPECT_THROW(umeyamaAlignment(Eigen::Matrix3Xd(3, 0), Eigen::Matrix3Xd(3, 0), false), quasiloc::core::InputError);
    Eigen::Matrix3Xd same(3, 4);
    same.setOnes();
    EXPECT_THROW(umeyamaAlignment(same, same, true), quasiloc::core::InputError);
}
