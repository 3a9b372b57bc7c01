#pragma once
// The map terms' unit-test scene: a floor (z = 0) with a wall across it ahead (x = wall_x), and a camera above the
// floor looking along world x.
#include <Eigen/Geometry>
#include <quasiloc/map/lidar_map.h>

namespace quasiloc::tracking::test
{
/** Floor points for x in [x_min, x_max] and |y| <= half_width, wall points for |y| <= half_width up to wall_height,
 *  every `step` metres, reflectivity 0.5. */
inline map::LidarMap floorAndWall(float x_min, float x_max, float wall_x, float half_width, float wall_height,
                                  float step)
{
    map::LidarMap map;
    for (float x = x_min; x <= x_max; x += step)
        for (float y = -half_width; y <= half_width; y += step) map.addPoint(x, y, 0, 0.5f);
    for (float y = -half_width; y <= half_width; y += step)
        for (float z = 0; z <= wall_height; z += step) map.addPoint(wall_x, y, z, 0.5f);
    return map;
}

/** T_world_cam of a camera height_m above the origin looking along world x (camera z -> world x, camera x -> world
 *  -y, camera y -> world -z). */
inline Eigen::Isometry3d cameraAlongX(double height_m)
{
    Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
    T_world_cam.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
    T_world_cam.translation() = Eigen::Vector3d(0, 0, height_m);
    return T_world_cam;
}
}  // namespace quasiloc::tracking::test
