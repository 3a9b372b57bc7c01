#include <quasiloc/tracking/pixel_rays.h>

namespace quasiloc::tracking
{
PixelRays::PixelRays(const core::CameraModel& camera)
    : x(camera.height, camera.width, CV_32FC1), y(camera.height, camera.width, CV_32FC1)
{
    for (int v = 0; v < camera.height; ++v)
        for (int u = 0; u < camera.width; ++u)
        {
            const Eigen::Vector3d r = camera.unproject(Eigen::Vector2d(u, v));  // z = 1
            x.at<float>(v, u) = float(r.x());
            y.at<float>(v, u) = float(r.y());
        }
}
}  // namespace quasiloc::tracking
