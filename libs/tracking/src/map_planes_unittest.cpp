// Map planes (map_planes.h): a point in the middle of a wall has the wall as its one candidate, a point beside a
// wall-floor crease has both planes with most probability on its own, and a point off every surface has none.
#include <gtest/gtest.h>

#include <quasiloc/tracking/map_planes.h>

using namespace quasiloc;

namespace
{
const core::CameraModel kCamera = core::CameraModel::pinhole(320, 240, 300, 300, 160, 120);

/** Seen from the identity pose: a wall at z = 3 and, below it, a floor at y = 1 (y down). */
quasi::QuasiImage room()
{
    quasi::QuasiImage q;
    q.depth.create(kCamera.height, kCamera.width, CV_32FC1);
    for (int v = 0; v < q.depth.rows; ++v)
        for (int u = 0; u < q.depth.cols; ++u)
        {
            const double yn = (v - kCamera.cy) / kCamera.fy;
            q.depth.at<float>(v, u) = float(yn > 0 ? std::min(3.0, 1.0 / yn) : 3.0);
        }
    return q;  // T_world_cam: identity
}
}  // namespace

TEST(MapPlanes, CandidatesFollowTheSurfacesAroundThePoint)
{
    const quasi::QuasiImage q = room();
    tracking::MapPlaneAssociator a(kCamera, tracking::MapPlaneOptions{});
    // The crease projects at v = cy + fy / 3 = 220. Points: mid-wall; on the wall 5 px above the crease; 0.5 m in
    // front of the wall.
    const Eigen::Vector3d mid(0.0, -0.5, 3.0), near_crease(0.0, (215 - 120) / 300.0 * 3.0, 3.0), off(0.3, -0.5, 2.5);
    const auto f = a.associate({mid, near_crease, off}, {0.02, 0.02, 0.02}, q, Eigen::Isometry3d::Identity());
    ASSERT_EQ(f.size(), 2u);  // the point off every surface has no candidate
    ASSERT_EQ(f[0].candidates.size(), 1u);
    EXPECT_NEAR(std::abs(f[0].candidates[0].n_map.z()), 1.0, 1e-3);  // the wall's normal
    EXPECT_NEAR(std::abs(f[0].candidates[0].d), 3.0, 1e-3);
    EXPECT_NEAR(f[0].candidates[0].probability, 1.0, 1e-9);
    ASSERT_EQ(f[1].candidates.size(), 2u);  // wall and floor
    int wall = std::abs(f[1].candidates[0].n_map.z()) > 0.9 ? 0 : 1;
    EXPECT_NEAR(std::abs(f[1].candidates[1 - wall].n_map.y()), 1.0, 1e-3);  // the floor's normal
    EXPECT_GT(f[1].candidates[wall].probability, 0.9);
    EXPECT_NEAR(f[1].candidates[0].probability + f[1].candidates[1].probability, 1.0, 1e-9);
}
