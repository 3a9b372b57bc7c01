// Robust PnP: pose, inlier mask and statistics on a synthetic scene with outliers, for every method and a
// distorted camera; bad input.
#include <gtest/gtest.h>

#include <quasiloc/core/error.h>
#include <quasiloc/estimation/absolute_pose.h>
#include <random>

#include "test_helpers.h"

using namespace quasiloc::estimation;

namespace
{
struct PnpScene
{
    std::vector<Eigen::Vector2d> px;
    std::vector<Eigen::Vector3d> X;
    std::vector<char> is_inlier;
    Eigen::Isometry3d T_cam_world;
};

PnpScene makeScene(const quasiloc::core::CameraModel& cam, int n, double outlier_rate, double noise_px, unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(0, 1);
    std::normal_distribution<double> N(0, noise_px);
    PnpScene s;
    s.T_cam_world = test::makePose(Eigen::Vector3d(0.4, -1.0, 0.3), Eigen::Vector3d(0.5, -1.0, 2.0));
    const Eigen::Isometry3d T_world_cam = s.T_cam_world.inverse();
    while (static_cast<int>(s.X.size()) < n)
    {
        const Eigen::Vector2d px(U(rng) * cam.width, U(rng) * cam.height);
        const Eigen::Vector3d p_cam = cam.unproject(px) * (2.0 + 8.0 * U(rng));
        const bool outlier = U(rng) < outlier_rate;
        s.X.push_back(T_world_cam * p_cam);
        s.px.push_back(outlier ? Eigen::Vector2d(U(rng) * cam.width, U(rng) * cam.height)
                               : Eigen::Vector2d(px + Eigen::Vector2d(N(rng), N(rng))));
        s.is_inlier.push_back(!outlier);
    }
    return s;
}

void checkMethod(PnpMethod method, const quasiloc::core::CameraModel& cam)
{
    const PnpScene s = makeScene(cam, 200, 0.4, 0.5, 11);
    AbsolutePoseOptions opt;
    opt.method = method;
    Eigen::Isometry3d T;
    AbsolutePoseStats st;
    ASSERT_TRUE(estimateAbsolutePose(opt, s.px, s.X, cam, &T, &st)) << int(method);
    EXPECT_LT((T.translation() - s.T_cam_world.translation()).norm(), 0.02) << int(method);
    EXPECT_LT(logSO3(T.linear().transpose() * s.T_cam_world.linear()).norm(), 2e-3) << int(method);
    int true_pos = 0, false_pos = 0, inliers = 0;
    for (size_t i = 0; i < s.px.size(); ++i)
    {
        inliers += s.is_inlier[i];
        true_pos += s.is_inlier[i] && st.inlier_mask[i];
        false_pos += !s.is_inlier[i] && st.inlier_mask[i];
    }
    EXPECT_GE(true_pos, 0.97 * inliers) << int(method);
    EXPECT_LE(false_pos, 3) << int(method);  // a random outlier may land within 2 px of its reprojection
    EXPECT_EQ(st.num_inliers, true_pos + false_pos);
    EXPECT_GT(st.iterations, 1);
    EXPECT_LE(st.refinement_final_cost, st.refinement_initial_cost);
    EXPECT_LT(st.mean_inlier_error_px, 1.0);
}
}  // namespace

TEST(AbsolutePose, MagsacRecoversPoseAndInliers) { checkMethod(PnpMethod::Magsac, test::pinholeCamera().model); }
TEST(AbsolutePose, UsacDefaultRecoversPoseAndInliers)
{
    checkMethod(PnpMethod::UsacDefault, test::pinholeCamera().model);
}
TEST(AbsolutePose, ClassicRansacRecoversPoseAndInliers) { checkMethod(PnpMethod::Ransac, test::pinholeCamera().model); }

TEST(AbsolutePose, WorksWithEquidistantCamera)
{
    quasiloc::core::CameraModel cam = quasiloc::core::CameraModel::pinhole(640, 480, 300, 300, 320, 240);
    cam.model = quasiloc::core::DistortionModel::Equidistant;
    cam.dist = {-0.01, 0.02, -0.01, 0.002, 0};
    checkMethod(PnpMethod::Magsac, cam);
}

TEST(AbsolutePose, RejectsBadInput)
{
    const auto cam = test::pinholeCamera().model;
    AbsolutePoseOptions opt;
    Eigen::Isometry3d T;
    EXPECT_THROW(estimateAbsolutePose(opt, {Eigen::Vector2d(1, 2)}, {}, cam, &T, nullptr), quasiloc::core::InputError);
    PnpScene s = makeScene(cam, 10, 0.0, 0.1, 2);
    s.X[3].x() = std::nan("");
    EXPECT_THROW(estimateAbsolutePose(opt, s.px, s.X, cam, &T, nullptr), quasiloc::core::InputError);
    EXPECT_FALSE(estimateAbsolutePose(opt, {s.px[0], s.px[1], s.px[2]}, {s.X[0], s.X[1], s.X[2]}, cam, &T, nullptr));
    opt.min_inliers = 3;
    EXPECT_THROW(opt.check("test"), quasiloc::core::InputError);
}
