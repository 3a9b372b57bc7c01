// MapRefiner on a simulated frame: every method (features, guided, direct, combined) brings a pose perturbed by
// 0.1 m / 1 deg (bench_crossmodal's level (a)) back to within its success bounds (< 0.1 m, < 0.5 deg). The camera
// image is the map's own quasi-image at the true pose: no modality gap, so a failure here is the machinery's
// (matching, lifting, PnP, gating, alignment), not the descriptors'.
#include <gtest/gtest.h>

#include <quasiloc/core/pose.h>
#include <quasiloc/estimation/map_refinement.h>
#include <quasiloc/estimation/pose_parametrization.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <quasiloc/quasi/synthetic_scene.h>

using namespace quasiloc;

namespace
{
Eigen::Isometry3d trueCameraPose()
{
    // Inside the synthetic room, looking along +x and a little down, towards a corner with boxes.
    Eigen::Matrix3d R;
    R << 0, 0, 1, -1, 0, 0, 0, -1, 0;  // camera z -> world x, camera x -> world -y, camera y -> world -z
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R *
                 Eigen::AngleAxisd(0.15, Eigen::Vector3d::UnitX()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(-2.0, -0.5, 1.4);
    return T;
}

Eigen::Isometry3d perturbed(const Eigen::Isometry3d& T, double t_m, double rot_deg, int seed)
{
    const Eigen::Vector3d a = Eigen::Vector3d(std::sin(seed), std::cos(3 * seed), std::sin(5 * seed + 1)).normalized();
    const Eigen::Vector3d b = Eigen::Vector3d(std::cos(2 * seed), std::sin(7 * seed), std::cos(seed + 2)).normalized();
    estimation::Vector6d d;
    d << a * rot_deg * M_PI / 180, b * t_m;
    return estimation::boxPlus(T, d);
}
}  // namespace

TEST(MapRefinement, EveryMethodRecoversFromLevelA)
{
    const map::LidarMap map = quasi::makeSyntheticRoom(400000);
    const core::CameraModel camera = core::CameraModel::pinhole(752, 480, 458.0, 457.0, 367.0, 248.0);
    quasi::QuasiRenderer renderer(map, quasi::QuasiOptions{});
    frontend::FrontendOptions fo;
    frontend::Frontend frontend(fo);
    estimation::MapRefinementOptions ro;
    estimation::MapRefiner refiner(ro, renderer, frontend);

    const Eigen::Isometry3d T_true = trueCameraPose();
    quasi::QuasiImage q;
    renderer.render(core::fromIsometry(T_true), camera, q);
    refiner.setImage(q.gray, camera);
    for (const auto method : {estimation::RefinementMethod::Features, estimation::RefinementMethod::Guided,
                              estimation::RefinementMethod::Direct, estimation::RefinementMethod::Combined})
        for (int seed = 1; seed <= 3; ++seed)
        {
            const Eigen::Isometry3d T0 = perturbed(T_true, 0.1, 1.0, seed);
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
