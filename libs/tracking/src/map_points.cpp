// Map points for the point factor (map_points.h).
#include <quasiloc/tracking/map_points.h>

#include <quasiloc/frontend/lifting.h>

namespace quasiloc::tracking
{
std::vector<estimation::PointMatch> associateMapPoints(
    const frontend::Features& camera_features, const frontend::Features& quasi_features, const quasi::QuasiImage& q,
    const map::LidarMap& map, const core::CameraModel& camera, const Eigen::Isometry3d& T_world_cam,
    const frontend::PointMatchingOptions& matching, const MapPointOptions& options)
{
    // The quasi-image's keypoints that lift, with their map points' projections at T_world_cam as search centres.
    frontend::Features lifted = quasi_features;
    lifted.keypoints.clear();
    lifted.descriptors = cv::Mat();
    std::vector<Eigen::Vector3d> points;
    frontend::SearchRegion region;
    region.radius_px = options.window_px;
    const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();
    for (size_t k = 0; k < quasi_features.keypoints.size(); ++k)
    {
        const auto p = frontend::liftPixel(q, map, quasi_features.keypoints[k].pt, options.lift_radius_px);
        if (!p) continue;
        Eigen::Vector2d u;
        if (!camera.project(T_cam_world * p->p_world.cast<double>(), u)) continue;
        lifted.keypoints.push_back(quasi_features.keypoints[k]);
        lifted.descriptors.push_back(quasi_features.descriptors.row(int(k)));
        points.push_back(p->p_world.cast<double>());
        region.centers.emplace_back(float(u.x()), float(u.y()));
    }
    std::vector<estimation::PointMatch> out;
    if (points.empty() || camera_features.keypoints.empty()) return out;
    for (const frontend::PointMatch& m : frontend::matchPoints(lifted, camera_features, matching, &region))
    {
        estimation::PointMatch pm;
        const cv::Point2f& px = camera_features.keypoints[size_t(m.train)].pt;
        pm.px = Eigen::Vector2d(px.x, px.y);
        pm.p_map = points[size_t(m.query)];
        pm.sigma_px = options.sigma_px;
        out.push_back(pm);
    }
    return out;
}

int countCorrectMatches(const std::vector<estimation::PointMatch>& matches, const core::CameraModel& camera,
                        const Eigen::Isometry3d& T_world_cam_true, double correct_px)
{
    const Eigen::Isometry3d T_cam_world = T_world_cam_true.inverse();
    int n = 0;
    for (const estimation::PointMatch& m : matches)
    {
        Eigen::Vector2d u;
        n += camera.project(T_cam_world * m.p_map, u) && (u - m.px).norm() <= correct_px;
    }
    return n;
}

}  // namespace quasiloc::tracking
