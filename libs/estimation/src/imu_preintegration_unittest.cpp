// IMU preintegration: deltas against a closed-form motion, bias Jacobians and factor Jacobians against
// numeric differentiation, covariance against Monte Carlo, and the bias random-walk factor.
#include <gtest/gtest.h>

#include <quasiloc/estimation/imu_preintegration.h>
#include <random>

#include "test_helpers.h"

using namespace quasiloc::estimation;
using quasiloc::estimation::test::makePose;
using quasiloc::estimation::test::numericJacobian;
using quasiloc::estimation::test::numericPoseJacobian;
using quasiloc::estimation::test::relativeError;

namespace
{
constexpr double kDt = 0.005;  // 200 Hz

/** Samples of a constant rotation rate and constant body-frame specific force, n steps. */
ImuPreintegration constantMotion(const Eigen::Vector3d& w, const Eigen::Vector3d& f, int n,
                                 const Eigen::Vector3d& bg = Eigen::Vector3d::Zero(),
                                 const Eigen::Vector3d& ba = Eigen::Vector3d::Zero())
{
    ImuPreintegration pre(ImuNoise{}, bg, ba);
    for (int k = 0; k < n; ++k)
        pre.integrate(f + 0.3 * Eigen::Vector3d(std::sin(0.1 * k), std::cos(0.07 * k), 0.5),
                      w + Eigen::Vector3d(0, 0.2 * std::sin(0.05 * k), 0), kDt);
    return pre;
}
}  // namespace

TEST(ImuPreintegration, FreeFallAndStaticAgreeWithPhysics)
{
    // A static IMU measures f = -g in the body frame: the predicted state must stay put.
    const ImuNoise noise;
    ImuPreintegration pre(noise, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
    const Eigen::Isometry3d T_i = makePose(Eigen::Vector3d(0.3, -0.2, 1.0), Eigen::Vector3d(1, 2, 3));
    const Eigen::Vector3d f = T_i.linear().transpose() * (-noise.gravity());
    for (int k = 0; k < 100; ++k) pre.integrate(f, Eigen::Vector3d::Zero(), kDt);
    Eigen::Isometry3d T_j;
    Eigen::Vector3d v_j;
    pre.predict(T_i, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), T_j, v_j);
    EXPECT_LT((T_j.translation() - T_i.translation()).norm(), 1e-9);
    EXPECT_LT(v_j.norm(), 1e-9);
    EXPECT_NEAR(pre.dt(), 0.5, 1e-12);

    // Constant rate about z for 0.5 s: dR = Exp(w t).
    ImuPreintegration rot(noise, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
    for (int k = 0; k < 100; ++k) rot.integrate(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 0.8), kDt);
    EXPECT_LT((rot.deltaR() - expSO3(Eigen::Vector3d(0, 0, 0.4))).norm(), 1e-12);
}

TEST(ImuPreintegration, BiasJacobiansMatchRepropagation)
{
    const Eigen::Vector3d w(0.3, -0.5, 0.8), f(0.5, 0.2, 9.7);
    const ImuPreintegration pre = constantMotion(w, f, 60);
    // Delta as a function of the biases, by re-integrating from scratch with new linearisation biases.
    auto deltas = [&](const Eigen::VectorXd& b) {
        ImuPreintegration p2 = pre;
        p2.repropagate(b.head<3>(), b.tail<3>());
        Eigen::VectorXd out(9);
        out << logSO3(pre.deltaR().transpose() * p2.deltaR()), p2.deltaV(), p2.deltaP();
        return out;
    };
    const Eigen::MatrixXd num = numericJacobian(deltas, Eigen::VectorXd::Zero(6), 1e-6);
    Eigen::MatrixXd ana(9, 6);
    ana << pre.dR_dbg(), Eigen::Matrix3d::Zero(), pre.dv_dbg(), pre.dv_dba(), pre.dp_dbg(), pre.dp_dba();
    EXPECT_LT(relativeError(ana, num), 1e-5) << ana << "\n\n" << num;
}

TEST(ImuPreintegration, CovarianceMatchesMonteCarlo)
{
    const Eigen::Vector3d w(0.3, -0.5, 0.8), f(0.5, 0.2, 9.7);
    ImuNoise noise;
    noise.gyro_noise_density = 2e-3;
    noise.acc_noise_density = 2e-2;
    const int n = 40, trials = 1500;
    ImuPreintegration nominal(noise, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
    for (int k = 0; k < n; ++k) nominal.integrate(f, w, kDt);
    std::mt19937 rng(5);
    std::normal_distribution<double> N(0, 1);
    Matrix9d cov = Matrix9d::Zero();
    for (int t = 0; t < trials; ++t)
    {
        ImuPreintegration p(noise, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
        const double sg = noise.gyro_noise_density / std::sqrt(kDt), sa = noise.acc_noise_density / std::sqrt(kDt);
        for (int k = 0; k < n; ++k)
            p.integrate(f + sa * Eigen::Vector3d(N(rng), N(rng), N(rng)),
                        w + sg * Eigen::Vector3d(N(rng), N(rng), N(rng)), kDt);
        Vector9d e;
        e << logSO3(nominal.deltaR().transpose() * p.deltaR()), p.deltaV() - nominal.deltaV(),
            p.deltaP() - nominal.deltaP();
        cov += e * e.transpose() / trials;
    }
    // Diagonal within 15 % (Monte Carlo with 1500 trials: ~4 % standard error on a variance).
    for (int i = 0; i < 9; ++i) EXPECT_NEAR(cov(i, i) / nominal.covariance()(i, i), 1.0, 0.15) << "component " << i;
}

TEST(ImuPreintegration, GapStepCarriesTheUnmeasuredMotionsVariance)
{
    // Dropped samples: the held sample covers 0.1 s. Its step adds (sigma * dt)^2 per axis to the velocity's and
    // the rotation's variance beyond the sensor noise's; steps no longer than gap_s are untouched.
    const Eigen::Vector3d w(0.3, -0.5, 0.8), f(0.5, 0.2, 9.7);
    ImuNoise with_gap, without_gap;
    with_gap.gap_acc_sigma = 1.0;
    with_gap.gap_gyro_sigma = 0.25;
    without_gap.gap_acc_sigma = without_gap.gap_gyro_sigma = 0;
    ImuPreintegration a(with_gap, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
    ImuPreintegration b(without_gap, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
    for (int k = 0; k < 20; ++k) a.integrate(f, w, kDt), b.integrate(f, w, kDt);
    EXPECT_EQ(a.covariance(), b.covariance()) << "a 5 ms step is not a gap";
    const double gap = 0.1;
    ASSERT_GT(gap, with_gap.gap_s);
    a.integrate(f, w, gap);
    b.integrate(f, w, gap);
    const Matrix9d extra = a.covariance() - b.covariance();
    const double acc_var = std::pow(with_gap.gap_acc_sigma * gap, 2),
                 gyro_var = std::pow(with_gap.gap_gyro_sigma * gap, 2);
    EXPECT_NEAR((extra.block<3, 3>(3, 3).trace()), 3 * acc_var, 1e-9) << "velocity";
    EXPECT_NEAR((extra.block<3, 3>(0, 0).trace()), 3 * gyro_var, 0.02 * 3 * gyro_var) << "rotation (J_r of 0.1 s)";
    EXPECT_NEAR((extra.block<3, 3>(6, 6).trace()), 3 * std::pow(0.5 * with_gap.gap_acc_sigma * gap * gap, 2), 1e-9)
        << "position";
    // The deltas themselves do not change: the gap widens the uncertainty only.
    EXPECT_EQ(a.deltaV(), b.deltaV());
}

TEST(ImuPreintegration, GapLongerThanTheMaximumGetsNoAddedVariance)
{
    // A 1 s hole is left to the loss check: its step carries the sensor noise alone, like without the option.
    const Eigen::Vector3d w(0.3, -0.5, 0.8), f(0.5, 0.2, 9.7);
    ImuNoise with_gap, without_gap;
    without_gap.gap_acc_sigma = without_gap.gap_gyro_sigma = 0;
    ASSERT_GT(with_gap.gap_acc_sigma, 0) << "on by default";
    const double long_gap = 1.0, short_gap = 0.4;
    ASSERT_GT(long_gap, with_gap.gap_max_s);
    ASSERT_LE(short_gap, with_gap.gap_max_s);
    ImuPreintegration a(with_gap, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
    ImuPreintegration b(without_gap, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
    a.integrate(f, w, long_gap), b.integrate(f, w, long_gap);
    EXPECT_EQ(a.covariance(), b.covariance());
    a.integrate(f, w, short_gap), b.integrate(f, w, short_gap);
    EXPECT_GT((a.covariance().block<3, 3>(3, 3).trace()), (b.covariance().block<3, 3>(3, 3).trace() + 0.1))
        << "a 0.4 s gap adds (1 m/s^2 * 0.4 s)^2 per axis to the velocity's variance";
}

TEST(ImuFactor, JacobiansMatchNumeric)
{
    const ImuPreintegration pre = constantMotion(Eigen::Vector3d(0.3, -0.5, 0.8), Eigen::Vector3d(0.5, 0.2, 9.7), 40,
                                                 Eigen::Vector3d(0.01, -0.02, 0.005), Eigen::Vector3d(0.05, 0.1, -0.1));
    const ImuFactor factor(pre);
    const Eigen::Isometry3d T_i = makePose(Eigen::Vector3d(0.2, 0.1, -0.4), Eigen::Vector3d(1, 2, 0.5));
    const Eigen::Isometry3d T_j = makePose(Eigen::Vector3d(0.3, 0.05, -0.2), Eigen::Vector3d(1.3, 2.1, 0.45));
    Vector9d sb_i, sb_j;
    sb_i << 0.5, 0.1, -0.1, 0.012, -0.018, 0.006, 0.06, 0.09, -0.12;  // biases off the linearisation point
    sb_j << 0.6, 0.2, -0.05, 0.01, -0.02, 0.005, 0.05, 0.1, -0.1;
    Vector9d r;
    ImuFactor::Jac96 J_Ti, J_Tj;
    ImuFactor::Jac99 J_sbi, J_sbj;
    factor.linearize(T_i, sb_i, T_j, sb_j, r, &J_Ti, &J_sbi, &J_Tj, &J_sbj);
    auto res = [&](const Eigen::Isometry3d& Ti, const Vector9d& si, const Eigen::Isometry3d& Tj, const Vector9d& sj) {
        Vector9d rr;
        factor.linearize(Ti, si, Tj, sj, rr, nullptr, nullptr, nullptr, nullptr);
        return Eigen::VectorXd(rr);
    };
    const auto nTi = numericPoseJacobian([&](const Eigen::Isometry3d& X) { return res(X, sb_i, T_j, sb_j); }, T_i);
    const auto nTj = numericPoseJacobian([&](const Eigen::Isometry3d& X) { return res(T_i, sb_i, X, sb_j); }, T_j);
    const auto nsi = numericJacobian([&](const Eigen::VectorXd& x) { return res(T_i, Vector9d(x), T_j, sb_j); }, sb_i);
    const auto nsj = numericJacobian([&](const Eigen::VectorXd& x) { return res(T_i, sb_i, T_j, Vector9d(x)); }, sb_j);
    EXPECT_LT(relativeError(J_Ti, nTi), 1e-6) << J_Ti << "\n\n" << nTi;
    EXPECT_LT(relativeError(J_Tj, nTj), 1e-6) << J_Tj << "\n\n" << nTj;
    EXPECT_LT(relativeError(J_sbi, nsi), 1e-6) << J_sbi << "\n\n" << nsi;
    EXPECT_LT(relativeError(J_sbj, nsj), 1e-6) << J_sbj << "\n\n" << nsj;
}

TEST(ImuFactor, ZeroResidualAtPredictedState)
{
    const ImuPreintegration pre = constantMotion(Eigen::Vector3d(0.3, -0.5, 0.8), Eigen::Vector3d(0.5, 0.2, 9.7), 40);
    const ImuFactor factor(pre);
    const Eigen::Isometry3d T_i = makePose(Eigen::Vector3d(0.2, 0.1, -0.4), Eigen::Vector3d(1, 2, 0.5));
    const Eigen::Vector3d v_i(0.4, -0.2, 0.1);
    Eigen::Isometry3d T_j;
    Eigen::Vector3d v_j;
    pre.predict(T_i, v_i, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), T_j, v_j);
    Vector9d sb_i = Vector9d::Zero(), sb_j = Vector9d::Zero();
    sb_i.head<3>() = v_i;
    sb_j.head<3>() = v_j;
    Vector9d r;
    factor.linearize(T_i, sb_i, T_j, sb_j, r, nullptr, nullptr, nullptr, nullptr);
    EXPECT_LT(r.norm(), 1e-6);
    // A 1 cm error in p_j is seen (the residual grows by ~ 1 cm / sigma_p).
    T_j.translation().x() += 0.01;
    factor.linearize(T_i, sb_i, T_j, sb_j, r, nullptr, nullptr, nullptr, nullptr);
    EXPECT_GT(r.norm(), 1.0);
}

TEST(BiasRandomWalkFactor, ResidualAndJacobians)
{
    ImuNoise noise;
    const BiasRandomWalkFactor f(noise, 0.25);
    double sb_i[9] = {1, 2, 3, 0.01, 0.02, 0.03, 0.1, 0.2, 0.3};
    double sb_j[9] = {4, 5, 6, 0.011, 0.02, 0.03, 0.1, 0.2, 0.35};
    const double* params[2] = {sb_i, sb_j};
    double r[6], Ji[54], Jj[54];
    double* jac[2] = {Ji, Jj};
    ASSERT_TRUE(f.Evaluate(params, r, jac));
    EXPECT_NEAR(r[0], 0.001 / (noise.gyro_random_walk * 0.5), 1e-6);
    EXPECT_NEAR(r[5], 0.05 / (noise.acc_random_walk * 0.5), 1e-6);
    EXPECT_EQ(Ji[0], 0.0);                                           // velocity does not enter
    EXPECT_NEAR(Jj[3], 1.0 / (noise.gyro_random_walk * 0.5), 1e-6);  // row 0, column 3 (b_g x)
    EXPECT_NEAR(Ji[3], -Jj[3], 1e-12);
}
