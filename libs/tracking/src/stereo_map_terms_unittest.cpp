// stereoMapTermsByTruncation: far stereo points keep a truncation of their own depth noise, and the terms together
// weigh what one term of all the points would.
#include <gtest/gtest.h>

#include <cmath>
#include <quasiloc/map/distance_field.h>
#include <quasiloc/tracking/tracker.h>

#include "floor_wall_scene.h"

using namespace quasiloc;

TEST(StereoMapTerms, WithoutSigmasOneTermAtTheFixedTruncation)
{
    const std::vector<Eigen::Vector3d> p{{0, 0, 2}, {0, 0, 10}, {0, 0, 25}};
    const std::vector<double> sigma{0.02, 0.1, 0.8};
    const auto terms = tracking::stereoMapTermsByTruncation(p, sigma, 0.15, 0, 50);
    ASSERT_EQ(terms.size(), 1u);
    EXPECT_DOUBLE_EQ(terms[0].truncation_m, 0.15);
    EXPECT_DOUBLE_EQ(terms[0].effective_points, 50);
    EXPECT_EQ(terms[0].p_cam.size(), 3u);
}

TEST(StereoMapTerms, FarPointsGetATruncationOfTheirSigmas)
{
    // Depth sigmas of a 0.54 m baseline, fx 721 rig at 0.25 px: about 0.005, 0.12 and 0.58 m at 3, 15 and 30 m.
    std::vector<Eigen::Vector3d> p;
    std::vector<double> sigma;
    for (int i = 0; i < 6; ++i) p.emplace_back(0, 0, 3), sigma.push_back(0.02);
    for (int i = 0; i < 3; ++i) p.emplace_back(0, 0, 15), sigma.push_back(0.12);
    p.emplace_back(0, 0, 30), sigma.push_back(0.58);
    const auto terms = tracking::stereoMapTermsByTruncation(p, sigma, 0.15, 3, 50);
    ASSERT_EQ(terms.size(), 3u);
    double effective = 0;
    size_t points = 0;
    for (const auto& t : terms)
    {
        effective += t.effective_points;
        points += t.p_cam.size();
        EXPECT_NEAR(t.effective_points, 50.0 * double(t.p_cam.size()) / 10.0, 1e-9);
        for (double s : t.sigma_m) EXPECT_GE(t.truncation_m, std::max(0.15, 3 * s) - 1e-9);
        // Rounded up by at most a step of sqrt(2).
        for (double s : t.sigma_m) EXPECT_LT(t.truncation_m, std::sqrt(2.0) * std::max(0.15, 3 * s) + 1e-9);
    }
    EXPECT_NEAR(effective, 50, 1e-9);
    EXPECT_EQ(points, p.size());
    EXPECT_DOUBLE_EQ(terms[0].truncation_m, 0.15);  // 3 x 0.02 is below the fixed truncation
    EXPECT_EQ(terms[0].p_cam.size(), 6u);
    EXPECT_GT(terms.back().truncation_m, 1.7);  // 3 x 0.58
}

TEST(StereoMapTerms, TheDepthNoiseCountsAlongTheMapsNormal)
{
    // A road (z = 0) and a wall ahead (x = 30); a camera 1.65 m above the road looking along world x.
    const map::LidarMap map = tracking::test::floorAndWall(0, 32, 30, 3, 4, 0.04f);
    map::DistanceFieldOptions o;
    o.voxel_m = 0.04;
    const map::DistanceField field = map::DistanceField::build(map, o);
    const Eigen::Isometry3d T_world_cam = tracking::test::cameraAlongX(1.65);
    const double map_sigma = 0.02, depth_sigma = 0.26, sigma = std::hypot(map_sigma, depth_sigma);
    // The road 20 m ahead, seen 4.7 degrees below the horizon: a share of 0.082 of the depth noise.
    const Eigen::Vector3d road_cam(0, 1.65, 20);
    const double road = tracking::sigmaAlongNormal(field, T_world_cam, road_cam, sigma, map_sigma);
    EXPECT_NEAR(road, std::hypot(map_sigma, depth_sigma * 1.65 / road_cam.norm()), 0.004);
    EXPECT_LT(road, 0.04);
    // The wall ahead faces the ray: the whole sigma.
    const double wall = tracking::sigmaAlongNormal(field, T_world_cam, Eigen::Vector3d(0.5, 0.5, 30), sigma, map_sigma);
    EXPECT_NEAR(wall, sigma, 0.01);
    // Far from every surface the field has no gradient: the whole sigma.
    EXPECT_DOUBLE_EQ(tracking::sigmaAlongNormal(field, T_world_cam, Eigen::Vector3d(0, -5, 10), sigma, map_sigma),
                     sigma);
}
