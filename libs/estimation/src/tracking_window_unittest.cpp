// The tracking window end to end: a single frame with points, lines and planes recovers the true pose in
// every weighting mode; a two-frame window with IMU and temporal stereo landmarks recovers pose and velocity
// and hands a positive-definite 15x15 marginal to the next window; the prior factors' Jacobians; options.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <mrpt/config/CConfigFileMemory.h>
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
#include <algorithm>
#include <quasiloc/estimation/synthetic_scene.h>
#include <quasiloc/estimation/tracking_window.h>

#include "test_helpers.h"

using namespace quasiloc::estimation;
using quasiloc::estimation::test::makePose;
using quasiloc::estimation::test::numericPoseJacobian;
using quasiloc::estimation::test::relativeError;

namespace
{
WindowInput singleFrameInput(const SyntheticFrame& f)
{
    WindowInput in;
    in.stereo = &f.stereo;
    in.prior = f.prior;
    in.current = f.guess;
    in.points = f.points;
    in.lines = f.lines;
    in.planes = f.planes;
    return in;
}
}  // namespace

TEST(TrackingWindow, SingleFrameRecoversTruthInEveryMode)
{
    SceneOptions so;
    so.pixel_noise = 0;
    so.lidar_noise_m = 0;
    so.stereo_noise_rel = 0;
    so.point_outlier_rate = 0;
    so.wrong_nominal_rate = 0;
    std::mt19937 rng(4);
    SyntheticFrame f = makeSyntheticFrame(so, rng);
    f.prior.information *= 1e-8;  // the guess is off: a prior at full strength would bias the result
    const WindowInput in = singleFrameInput(f);
    ASSERT_GT(in.lines.size(), 5u);
    ASSERT_GT(in.planes.size(), 2u);
    for (ReweightingMode mode : {ReweightingMode::Uniform, ReweightingMode::Observability, ReweightingMode::Full})
        for (Primitives prim : {Primitives::P, Primitives::L, Primitives::PL, Primitives::PLPlane})
        {
            EstimatorOptions eo;
            eo.primitives = prim;
            eo.inner_iterations = 10;
            ReweightingOptions ro;
            ro.mode = mode;
            WindowResult res;
            ASSERT_TRUE(estimateWindow(eo, ro, in, res));
            const Vector6d err = boxMinus(res.current.T_map_body, f.T_map_body_true);
            EXPECT_LT(err.norm(), 1e-5) << int(mode) << " " << int(prim) << " error " << err.transpose();
            EXPECT_EQ(res.reweighting.weight.size(), size_t(res.stats.structural_factors));
        }
}

TEST(TrackingWindow, TwoFramesWithImuAndLandmarks)
{
    SceneOptions so;
    so.pixel_noise = 0.5;
    so.wrong_nominal_rate = 0;
    so.point_outlier_rate = 0;
    std::mt19937 rng(9);
    const SyntheticFrame f = makeSyntheticFrame(so, rng);
    const ImuNoise noise;
    // Motion over 0.1 s ending at the frame's true pose: constant body rate and constant map acceleration.
    const double T_int = 0.1, dt = 0.005;
    const Eigen::Vector3d w(0.2, -0.3, 0.5), a_map(0.5, -0.2, 0.3), v_j(0.8, 0.1, -0.2);
    const Eigen::Isometry3d T_j = f.T_map_body_true;
    Eigen::Isometry3d T_i = Eigen::Isometry3d::Identity();
    T_i.linear() = T_j.linear() * expSO3(-w * T_int);
    const Eigen::Vector3d v_i = v_j - a_map * T_int;
    T_i.translation() = T_j.translation() - v_i * T_int - 0.5 * a_map * T_int * T_int;
    ImuPreintegration pre(noise, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
    for (double t = 0; t < T_int - 1e-9; t += dt)
    {
        const Eigen::Matrix3d R_mid = T_i.linear() * expSO3(w * (t + 0.5 * dt));
        pre.integrate(R_mid.transpose() * (a_map - noise.gravity()), w, dt);
    }

    WindowInput in;
    in.stereo = &f.stereo;
    in.has_previous = true;
    in.previous.T_map_body = T_i;
    in.previous.v_map = v_i;
    in.prior.mean = in.previous;
    in.prior.information.diagonal() << Eigen::Vector3d::Constant(1e6), Eigen::Vector3d::Constant(1e6),
        Eigen::Vector3d::Constant(1e4), Eigen::Vector3d::Constant(1e6), Eigen::Vector3d::Constant(1e4);
    in.imu = &pre;
    pre.predict(T_i, v_i, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), in.current.T_map_body, in.current.v_map);
    in.current.T_map_body =
        boxPlus(in.current.T_map_body, (Vector6d() << 0.01, -0.02, 0.01, 0.05, 0.03, -0.04).finished());
    in.points = f.points;
    in.lines = f.lines;
    in.planes = f.planes;
    // Temporal landmarks: the map points seen in both frames.
    for (const auto& p : f.points)
    {
        TemporalLandmark lm;
        lm.p_map_guess = p.p_map + Eigen::Vector3d(0.02, -0.01, 0.03);
        bool ok = true;
        for (auto [T, obs] : {std::pair{T_i, &lm.previous}, std::pair{T_j, &lm.current}})
        {
            const Eigen::Vector3d pl = T.inverse() * p.p_map;
            ok = ok && f.stereo.left.model.project(pl, obs->left_px) &&
                 f.stereo.right.project(f.stereo.T_left_right.inverse() * pl, obs->right_px);
        }
        if (ok) in.landmarks.push_back(lm);
    }
    ASSERT_GT(in.landmarks.size(), 20u);
    EstimatorOptions eo;
    eo.inner_iterations = 10;
    ReweightingOptions ro;
    WindowResult res;
    ASSERT_TRUE(estimateWindow(eo, ro, in, res));
    EXPECT_LT((res.current.T_map_body.translation() - T_j.translation()).norm(), 0.01);
    EXPECT_LT(logSO3(T_j.linear().transpose() * res.current.T_map_body.linear()).norm(), 2e-3);
    EXPECT_LT((res.current.v_map - v_j).norm(), 0.05);
    const Eigen::SelfAdjointEigenSolver<Matrix15d> eig(res.marginal.information);
    EXPECT_GT(eig.eigenvalues()[0], 0.0) << eig.eigenvalues().transpose();
    // Map factors make the current pose far better known than the previous one's prior alone would.
    const double pose_info = res.marginal.information.topLeftCorner<6, 6>().trace();
    EXPECT_GT(pose_info, 6e6);
    EXPECT_GT(res.stats.rounds, 0);
}

TEST(PriorFactors, JacobiansMatchNumeric)
{
    StatePrior prior;
    prior.mean.T_map_body = makePose(Eigen::Vector3d(0.3, -0.1, 0.2), Eigen::Vector3d(1, 2, 3));
    prior.mean.v_map = Eigen::Vector3d(0.1, 0.2, 0.3);
    Eigen::Matrix<double, 15, 15> A = Eigen::Matrix<double, 15, 15>::Random();
    prior.information = A * A.transpose() + Matrix15d::Identity();
    const StatePriorFactor f(prior);
    const Eigen::Isometry3d T = makePose(Eigen::Vector3d(0.35, -0.05, 0.1), Eigen::Vector3d(1.1, 2.1, 2.9));
    Eigen::Matrix<double, 9, 1> sb = Eigen::Matrix<double, 9, 1>::Constant(0.05);
    Vector15d r;
    Eigen::Matrix<double, 15, 6> J;
    f.linearize(T, sb, r, &J, nullptr);
    const auto num = numericPoseJacobian(
        [&](const Eigen::Isometry3d& X) {
            Vector15d rr;
            f.linearize(X, sb, rr, nullptr, nullptr);
            return Eigen::VectorXd(rr);
        },
        T);
    EXPECT_LT(relativeError(J, num), 1e-6);
    // r^T r equals the Mahalanobis distance with the stated information.
    Vector15d e;
    e << boxMinus(T, prior.mean.T_map_body),
        sb - (Eigen::Matrix<double, 9, 1>() << prior.mean.v_map, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero())
                 .finished();
    EXPECT_NEAR(r.squaredNorm(), e.dot(prior.information * e), 1e-8 * e.dot(prior.information * e));
}

TEST(Options, IniRoundTripAndCheck)
{
    mrpt::config::CConfigFileMemory cfg;
    cfg.write("Estimator", "primitives", "P+L");
    cfg.write("Reweighting", "mode", "observability");
    cfg.write("Reweighting", "tau", "250");
    EstimatorOptions eo;
    ReweightingOptions ro;
    eo.loadFromConfigFile(cfg, "Estimator");
    ro.loadFromConfigFile(cfg, "Reweighting");
    EXPECT_EQ(eo.primitives, Primitives::PL);
    EXPECT_FALSE(eo.usePlanes());
    EXPECT_EQ(ro.mode, ReweightingMode::Observability);
    EXPECT_EQ(ro.tau, 250.0);
    // Every key load reads is one save writes (core::loadOptionsChecked rejects the others).
    const auto rk = quasiloc::core::knownKeys(ro, "Reweighting");
    for (const char* k : {"mode", "tau", "beta", "kappa", "epsilon"})
        EXPECT_NE(std::find(rk.begin(), rk.end(), k), rk.end()) << k;
    const auto ek = quasiloc::core::knownKeys(eo, "Estimator");
    EXPECT_EQ(ek.size(), 13u);
    quasiloc::core::loadOptionsChecked(ro, cfg, "Reweighting", "test.ini");
    cfg.write("Reweighting", "taus", "1");
    EXPECT_THROW(quasiloc::core::loadOptionsChecked(ro, cfg, "Reweighting", "test.ini"), quasiloc::core::InputError);

    cfg.write("Reweighting", "tau", "abc");
    EXPECT_THROW(ro.loadFromConfigFile(cfg, "Reweighting"), quasiloc::core::InputError);
    cfg.write("Reweighting", "tau", "-1");
    EXPECT_THROW(ro.loadFromConfigFile(cfg, "Reweighting"), quasiloc::core::InputError);
    cfg.write("Estimator", "primitives", "P+plane");
    EXPECT_THROW(eo.loadFromConfigFile(cfg, "Estimator"), quasiloc::core::InputError);
    cfg.write("Estimator", "primitives", "P");
    cfg.write("Estimator", "robust_loss", "tukey");
    EXPECT_THROW(eo.loadFromConfigFile(cfg, "Estimator"), quasiloc::core::InputError);
}
