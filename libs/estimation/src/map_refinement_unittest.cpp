// MapRefiner on a simulated frame: every method (features, guided, direct, combined) brings a pose perturbed by
// 0.1 m / 1 deg (bench_crossmodal's level (a)) back to within its success bounds (< 0.1 m, < 0.5 deg). The camera
// image is the map's own quasi-image at the true pose: no modality gap, so a failure here is the machinery's
// (matching, lifting, PnP, gating, alignment), not the descriptors'.
#include <gtest/gtest.h>

#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/estimation/map_refinement.h>
#include <quasiloc/estimation/pose_parametrization.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <quasiloc/quasi/synthetic_scene.h>

#include "test_helpers.h"

using namespace quasiloc;

using estimation::test::perturbedPose;

namespace
{
/** The synthetic room, a refiner with default options, and the camera image = the quasi-image at the true pose. */
struct RoomRefiner
{
    const map::LidarMap map = quasi::makeSyntheticRoom(400000);
    const core::CameraModel camera = core::CameraModel::pinhole(752, 480, 458.0, 457.0, 367.0, 248.0);
    quasi::QuasiRenderer renderer{map, quasi::QuasiOptions{}};
    frontend::Frontend frontend{frontend::FrontendOptions{}};
    estimation::MapRefiner refiner{estimation::MapRefinementOptions{}, renderer, frontend};
    const Eigen::Isometry3d T_true = estimation::test::syntheticRoomCameraPose();

    explicit RoomRefiner(bool with_features)
    {
        quasi::QuasiImage q;
        renderer.render(core::fromIsometry(T_true), camera, q);
        refiner.setImage(q.gray, camera, with_features);
    }
};
}  // namespace

TEST(MapRefinement, EveryMethodRecoversFromLevelA)
{
    RoomRefiner room(true);
    estimation::MapRefiner& refiner = room.refiner;
    const Eigen::Isometry3d& T_true = room.T_true;
    for (const auto method : {estimation::RefinementMethod::Features, estimation::RefinementMethod::Guided,
                              estimation::RefinementMethod::Direct, estimation::RefinementMethod::Combined})
        for (int seed = 1; seed <= 3; ++seed)
        {
            const Eigen::Isometry3d T0 = perturbedPose(T_true, 0.1, 1.0, seed);
            const auto r = refiner.refine(method, T0, 0.1, M_PI / 180);
            const Eigen::Isometry3d E = T_true.inverse() * r.T_world_cam;
            const double err_m = E.translation().norm();
            const double err_deg = Eigen::AngleAxisd(E.linear()).angle() * 180 / M_PI;
            std::printf("%-9s seed %d: %.3f m %.3f deg, %d matches, %d inliers\n", estimation::toString(method).c_str(),
                        seed, err_m, err_deg, r.matches, r.inliers);
            EXPECT_TRUE(r.success) << estimation::toString(method) << " seed " << seed;
            EXPECT_LT(err_m, 0.1) << estimation::toString(method) << " seed " << seed;
            EXPECT_LT(err_deg, 0.5) << estimation::toString(method) << " seed " << seed;
        }
}

TEST(MapRefinement, APerCallPriorWeightReplacesTheOption)
{
    RoomRefiner room(false);
    estimation::MapRefiner& refiner = room.refiner;
    const Eigen::Isometry3d& T_true = room.T_true;
    const Eigen::Isometry3d T0 = perturbedPose(T_true, 0.1, 1.0, 1);
    const auto error_m = [&](const estimation::MapRefinementResult& r) {
        return (T_true.inverse() * r.T_world_cam).translation().norm();
    };
    // Without a prior the edges bring the pose back; a prior a million times the option's holds it at the start.
    const auto free = refiner.refine(estimation::RefinementMethod::Direct, T0, 0.1, M_PI / 180, 0.0);
    const auto held = refiner.refine(estimation::RefinementMethod::Direct, T0, 0.1, M_PI / 180, 2e5);
    EXPECT_LT(error_m(free), 0.05);
    EXPECT_GT(error_m(held), 0.09);
    EXPECT_THROW(refiner.refine(estimation::RefinementMethod::Direct, T0, 0.1, M_PI / 180, -1.0), core::InputError);
}

// The edge model from a half-resolution render ([Tracking] model_downscale = 2): its points sit on the same 4 x 4
// pixel blocks of the camera (each projects onto a block centre of the full-resolution image), and the alignment
// on the full-resolution edge field recovers the pose as the full-resolution model does.
TEST(MapRefinement, HalfResolutionModelLiesOnTheCamerasBlocksAndAligns)
{
    RoomRefiner room(false);
    estimation::MapRefiner& refiner = room.refiner;
    const int block = estimation::MapRefinementOptions{}.direct.model_block_px;
    for (int seed = 1; seed <= 3; ++seed)
    {
        const Eigen::Isometry3d T0 = perturbedPose(room.T_true, 0.1, 1.0, seed);
        const auto model = refiner.prepareDirect(room.camera, T0, false, 2);
        EXPECT_EQ(refiner.quasiImage().depth.cols, room.camera.width / 2);
        ASSERT_GT(model->edge_points_world.size(), 200u);
        double worst_px = 0;
        for (const Eigen::Vector3d& p : model->edge_points_world)
        {
            Eigen::Vector2d u;
            ASSERT_TRUE(room.camera.project(T0.inverse() * p, u));
            // A block centre: (b + 0.5) * block - 0.5 for an integer b.
            const Eigen::Array2d b = (u.array() + 0.5) / block - 0.5;
            worst_px = std::max(worst_px, ((b - b.round()) * block).abs().maxCoeff());
        }
        EXPECT_LT(worst_px, 1e-6) << "seed " << seed;
        const auto r = refiner.alignPrepared(model, T0, 0.1, M_PI / 180);
        const Eigen::Isometry3d E = room.T_true.inverse() * r.T_world_cam;
        EXPECT_TRUE(r.success) << "seed " << seed;
        EXPECT_LT(E.translation().norm(), 0.05) << "seed " << seed;
        EXPECT_LT(Eigen::AngleAxisd(E.linear()).angle() * 180 / M_PI, 0.5) << "seed " << seed;
    }
    EXPECT_THROW(refiner.prepareDirect(room.camera, room.T_true, false, 3), core::InputError);  // 3 does not divide 4
}
