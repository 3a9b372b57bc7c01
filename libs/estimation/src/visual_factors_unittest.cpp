// Analytic Jacobians of the visual factors against numeric differentiation through the pose manifold,
// the lifted Ceres Jacobian convention, and a pose solve that must recover the true pose.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <quasiloc/estimation/visual_factors.h>

#include "test_helpers.h"

using namespace quasiloc::estimation;
using quasiloc::estimation::test::makePose;
using quasiloc::estimation::test::numericJacobian;
using quasiloc::estimation::test::numericPoseJacobian;
using quasiloc::estimation::test::relativeError;

namespace
{
// A distorted camera and a non-trivial extrinsic, so that every term of the chain rule is exercised.
CameraGeometry distortedCamera()
{
    CameraGeometry cam;
    cam.model = quasiloc::core::CameraModel::pinhole(752, 480, 458.6, 457.3, 367.2, 248.4);
    cam.model.model = quasiloc::core::DistortionModel::RadTan;
    cam.model.dist = {-0.28, 0.074, 1.9e-4, 1.8e-5, 0.0};
    cam.T_body_cam = makePose(Eigen::Vector3d(0.01, -0.02, 1.55), Eigen::Vector3d(-0.02, 0.06, 0.01));
    return cam;
}

// T_map_body such that the points below (around map (0, 0, 4)) are in front of the camera.
Eigen::Isometry3d statePose(const CameraGeometry& cam)
{
    const Eigen::Isometry3d T_map_cam = makePose(Eigen::Vector3d(0.05, -0.1, 0.02), Eigen::Vector3d(0.1, -0.2, 0.3));
    return T_map_cam * cam.T_body_cam.inverse();
}
}  // namespace

TEST(VisualFactors, PointJacobianMatchesNumeric)
{
    const CameraGeometry cam = distortedCamera();
    const Eigen::Isometry3d T = statePose(cam);
    const PointReprojectionFactor f(cam, Eigen::Vector2d(300, 200), Eigen::Vector3d(0.7, -0.4, 4.5), 1.5);
    Eigen::Vector2d r;
    Matrix26d J;
    ASSERT_TRUE(f.linearize(T, r, &J));
    const auto num = numericPoseJacobian(
        [&](const Eigen::Isometry3d& X) {
            Eigen::Vector2d rr;
            f.linearize(X, rr, nullptr);
            return Eigen::VectorXd(rr);
        },
        T);
    EXPECT_LT(relativeError(J, num), 1e-6) << J << "\n\n" << num;
}

TEST(VisualFactors, LineJacobianMatchesNumeric)
{
    const CameraGeometry cam = distortedCamera();
    const Eigen::Isometry3d T = statePose(cam);
    std::vector<Eigen::Vector3d> support;
    for (int m = 0; m < 6; ++m) support.emplace_back(-0.5 + 0.2 * m, 0.3 + 0.05 * m, 4.0 + 0.1 * m);
    const PointToLineFactor f(cam, Eigen::Vector3d(0.3, 0.9, -250), support, 0.8);
    Eigen::VectorXd r;
    Eigen::Matrix<double, -1, 6> J;
    f.linearize(T, r, &J);
    ASSERT_EQ(r.size(), 6);
    const auto num = numericPoseJacobian(
        [&](const Eigen::Isometry3d& X) {
            Eigen::VectorXd rr;
            f.linearize(X, rr, nullptr);
            return rr;
        },
        T);
    EXPECT_LT(relativeError(J, num), 1e-6) << J << "\n\n" << num;
}

TEST(VisualFactors, PlaneJacobianMatchesNumeric)
{
    const CameraGeometry cam = distortedCamera();
    const Eigen::Isometry3d T = statePose(cam);
    const std::vector<Eigen::Vector3d> pts = {{0.1, 0.2, 3.0}, {-0.5, 0.1, 4.0}, {0.4, -0.3, 5.0}};
    const PointToPlaneFactor f(cam, pts, Eigen::Vector3d(0.2, -0.3, 0.9), 1.7, 0.03);
    Eigen::VectorXd r;
    Eigen::Matrix<double, -1, 6> J;
    f.linearize(T, r, &J);
    const auto num = numericPoseJacobian(
        [&](const Eigen::Isometry3d& X) {
            Eigen::VectorXd rr;
            f.linearize(X, rr, nullptr);
            return rr;
        },
        T);
    EXPECT_LT(relativeError(J, num), 1e-6) << J << "\n\n" << num;
}

TEST(VisualFactors, StereoJacobiansMatchNumeric)
{
    StereoGeometry stereo;
    stereo.left = distortedCamera();
    stereo.right = stereo.left.model;
    stereo.right.dist = {-0.28, 0.076, -1e-4, 1e-5, 0.0};
    stereo.T_left_right = makePose(Eigen::Vector3d(0.002, 0.01, -0.003), Eigen::Vector3d(0.11, -0.001, 0.0008));
    const Eigen::Isometry3d T = statePose(stereo.left);
    const Eigen::Vector3d X(0.4, 0.1, 4.2);
    const StereoLandmarkFactor f(stereo, Eigen::Vector2d(400, 250), Eigen::Vector2d(390, 251), 1.0);
    Eigen::Vector4d r;
    Eigen::Matrix<double, 4, 6> Jp;
    Eigen::Matrix<double, 4, 3> Jl;
    ASSERT_TRUE(f.linearize(T, X, r, &Jp, &Jl));
    const auto numP = numericPoseJacobian(
        [&](const Eigen::Isometry3d& P) {
            Eigen::Vector4d rr;
            f.linearize(P, X, rr, nullptr, nullptr);
            return Eigen::VectorXd(rr);
        },
        T);
    const auto numL = numericJacobian(
        [&](const Eigen::VectorXd& x) {
            Eigen::Vector4d rr;
            f.linearize(T, Eigen::Vector3d(x), rr, nullptr, nullptr);
            return Eigen::VectorXd(rr);
        },
        X);
    EXPECT_LT(relativeError(Jp, numP), 1e-6);
    EXPECT_LT(relativeError(Jl, numL), 1e-6);
}

TEST(VisualFactors, CeresSeesTangentJacobianThroughManifold)
{
    // Problem::Evaluate returns Jacobians in the tangent space: they must equal linearize()'s.
    const CameraGeometry cam = distortedCamera();
    const Eigen::Isometry3d T = statePose(cam);
    double params[7];
    poseToParams(T, params);
    ceres::Problem problem;
    auto* f = new PointReprojectionFactor(cam, Eigen::Vector2d(300, 200), Eigen::Vector3d(0.7, -0.4, 4.5), 1.0);
    problem.AddResidualBlock(f, nullptr, params);
    problem.SetManifold(params, new PoseManifold);
    ceres::CRSMatrix crs;
    double cost = 0;
    ASSERT_TRUE(problem.Evaluate(ceres::Problem::EvaluateOptions(), &cost, nullptr, nullptr, &crs));
    ASSERT_EQ(crs.num_cols, 6);
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
    for (int row = 0; row < crs.num_rows; ++row)
        for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k) J(row, crs.cols[k]) = crs.values[k];
    Eigen::Vector2d r;
    Matrix26d Jt;
    f->linearize(T, r, &Jt);
    EXPECT_LT(relativeError(J, Jt), 1e-12);
}

TEST(VisualFactors, PoseSolveRecoversTruth)
{
    const CameraGeometry cam = distortedCamera();
    const Eigen::Isometry3d T_true = statePose(cam);
    const Eigen::Isometry3d T_cam_map = camFromMap(T_true, cam.T_body_cam);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> U(-1, 1);
    ceres::Problem problem;
    double params[7];
    poseToParams(boxPlus(T_true, (Vector6d() << 0.03, -0.02, 0.04, 0.1, -0.1, 0.05).finished()), params);
    for (int i = 0; i < 40; ++i)
    {
        const Eigen::Vector3d p_cam(U(rng) * 2, U(rng) * 1.5, 4 + 2 * U(rng));
        Eigen::Vector2d px;
        ASSERT_TRUE(cam.model.project(p_cam, px));
        problem.AddResidualBlock(new PointReprojectionFactor(cam, px, T_cam_map.inverse() * p_cam, 1.0), nullptr,
                                 params);
    }
    problem.SetManifold(params, new PoseManifold);
    ceres::Solver::Options opt;
    ceres::Solver::Summary summary;
    ceres::Solve(opt, &problem, &summary);
    const Vector6d err = boxMinus(paramsToPose(params), T_true);
    EXPECT_LT(err.norm(), 1e-8) << summary.BriefReport();
}
