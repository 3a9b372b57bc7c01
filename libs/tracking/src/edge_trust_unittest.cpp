// The per-keyframe weight of the map edge term: full where the edge optimum fits the stereo as well as the
// prediction, falling with the stereo's growing distance to the map at the edge optimum, and the term left out where
// the edge optimum has moved the camera well off the surfaces the stereo sees.
#include <gtest/gtest.h>

#include <cmath>
#include <quasiloc/map/distance_field.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/tracking/edge_trust.h>

#include "floor_wall_scene.h"

using namespace quasiloc;

TEST(EdgeTrust, TheWeightFallsWithTheDisagreementInSigmas)
{
    EXPECT_DOUBLE_EQ(tracking::edgeTrustWeight(1.0, 0), 1.0) << "scale 0: off";
    EXPECT_DOUBLE_EQ(tracking::edgeTrustWeight(-0.5, 1), 1.0) << "the edge optimum fits the stereo better";
    EXPECT_DOUBLE_EQ(tracking::edgeTrustWeight(NAN, 1), 1.0) << "no stereo";
    EXPECT_NEAR(tracking::edgeTrustWeight(1.0, 1), std::exp(-0.5), 1e-12);
    EXPECT_NEAR(tracking::edgeTrustWeight(1.0, 2), std::exp(-0.125), 1e-12);
    EXPECT_LT(tracking::edgeTrustWeight(3.0, 1), tracking::kEdgeTrustDropWeight);
}

TEST(EdgeTrust, AnEdgeOptimumOffTheStereoSurfacesIsWeighedDownAndThenLeftOut)
{
    // A floor and a wall 2 m ahead of a camera looking along world x; stereo points on both, 2 cm sigmas.
    const map::LidarMap map = tracking::test::floorAndWall(-1, 2, 2, 1.5f, 2, 0.02f);
    map::DistanceFieldOptions o;
    o.voxel_m = 0.02;
    const map::DistanceField field = map::DistanceField::build(map, o);
    const Eigen::Isometry3d T_world_cam = tracking::test::cameraAlongX(1.0);
    tracking::StereoSurface stereo;  // the window's defaults: truncation 0.15 m, 50 effective points
    for (size_t i = 0; i < map.size(); i += 23)
    {
        const Eigen::Vector3d p = T_world_cam.inverse() * map.point(i).cast<double>();
        if (p.z() < 0.3 || std::abs(p.x()) > p.z() || std::abs(p.y()) > p.z()) continue;
        stereo.p_cam.push_back(p);
        stereo.sigma_m.push_back(0.02);
    }
    ASSERT_GT(stereo.p_cam.size(), 100u);
    const auto edgesAt = [&](const Eigen::Vector3d& offset) {
        Eigen::Isometry3d T_edges = T_world_cam;
        T_edges.translation() += offset;
        return T_edges;
    };
    const auto disagreement = [&](const Eigen::Vector3d& offset) {
        return tracking::edgeStereoDisagreement(field, T_world_cam, edgesAt(offset), stereo);
    };
    // Along the wall and the floor (world y) the stereo fits nearly as well. Toward the wall and up the disagreement
    // grows with the offset.
    const double along = disagreement({0, 0.05, 0}), d1 = disagreement({0.01, 0, 0.01}),
                 d2 = disagreement({0.02, 0, 0.02});
    EXPECT_LT(along, d1);  // 5 cm along: only the points at the patches' borders fall off
    EXPECT_GT(d1, 1.0);
    EXPECT_GT(d2, 1.5 * d1);
    const auto weigh = [&](const Eigen::Vector3d& offset, double scale, double* sigma_px) {
        std::vector<estimation::DirectEdgeTerm> terms(1);
        terms[0].sigma_px = 2.0;
        const double w = tracking::weighEdgeTerm(field, T_world_cam, edgesAt(offset), stereo, scale, terms);
        *sigma_px = terms.empty() ? NAN : terms[0].sigma_px;
        return w;
    };
    double sigma_px = 0;
    EXPECT_GT(weigh({0, 0.05, 0}, d1, &sigma_px), 0.85);
    // At one scale of disagreement the weight is exp(-1/2), applied to the pixel sigma.
    EXPECT_NEAR(weigh({0.01, 0, 0.01}, d1, &sigma_px), std::exp(-0.5), 1e-9);
    EXPECT_NEAR(sigma_px, 2.0 / std::sqrt(std::exp(-0.5)), 1e-9);
    // 8 cm off both surfaces: the term is left out.
    EXPECT_LT(weigh({0.08, 0, 0.08}, d1, &sigma_px), tracking::kEdgeTrustDropWeight);
    EXPECT_TRUE(std::isnan(sigma_px));
    // Scale 0: always trusted.
    EXPECT_EQ(weigh({0.08, 0, 0.08}, 0, &sigma_px), 1.0);
    EXPECT_EQ(sigma_px, 2.0);
}
