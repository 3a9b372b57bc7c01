// depthAwareInlier: a stereo point's depth tolerance counts along the map's normal only, so a point off a surface
// seen at a grazing angle is not explained by its (large) depth noise.
#include <gtest/gtest.h>

#include <quasiloc/map/distance_field.h>
#include <quasiloc/reloc/geometric_localizer.h>

using namespace quasiloc;

namespace
{
// A wall: the plane y = 0, x in [0, 4], z in [0, 2].
map::DistanceField wall()
{
    map::LidarMap map;
    const float s = 0.02f;
    for (float x = 0; x <= 4; x += s)
        for (float z = 0; z <= 2; z += s) map.addPoint(x, 0, z, 0.5f);
    map::DistanceFieldOptions o;
    o.voxel_m = 0.02;
    return map::DistanceField::build(map, o);
}
}  // namespace

TEST(DepthAwareInlier, AGrazingRayKeepsATightToleranceAFacingRayTheWholeOne)
{
    const map::DistanceField field = wall();
    const Eigen::Vector3f p(2, 0.3f, 1);               // 0.3 m in front of the wall
    const Eigen::Vector3f along(1, 0, 0);              // a ray along the wall (a street's facade seen far ahead)
    const Eigen::Vector3f facing(0, -1, 0);            // a ray onto the wall
    const Eigen::Vector3f oblique(1.7320508f, -1, 0);  // 60 degrees off the normal: |cos| = 0.5
    const double inlier_m = 0.06, depth_m = 0.6;       // 2 depth sigmas of a far point
    // The isotropic tolerance (0.66 m) explains the point whatever its ray.
    EXPECT_TRUE(reloc::depthAwareInlier(field, p, along, inlier_m, depth_m, false));
    EXPECT_TRUE(reloc::depthAwareInlier(field, p, facing, inlier_m, depth_m, false));
    // Along the normal: the grazing ray leaves 0.06 m, the facing one 0.66 m, the oblique one 0.36 m.
    EXPECT_FALSE(reloc::depthAwareInlier(field, p, along, inlier_m, depth_m, true));
    EXPECT_TRUE(reloc::depthAwareInlier(field, p, facing, inlier_m, depth_m, true));
    EXPECT_TRUE(reloc::depthAwareInlier(field, p, oblique, inlier_m, depth_m, true));
    EXPECT_FALSE(reloc::depthAwareInlier(field, Eigen::Vector3f(2, 0.42f, 1), oblique, inlier_m, depth_m, true));
    // A point on the wall is an inlier from any ray.
    EXPECT_TRUE(reloc::depthAwareInlier(field, Eigen::Vector3f(2, 0.01f, 1), along, inlier_m, depth_m, true));
}
