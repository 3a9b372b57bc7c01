#include <algorithm>
#include <quasiloc/map/world_scan.h>

namespace quasiloc::map
{
WorldScan toWorld(LidarScan&& scan, const ScanPoses& poses, size_t i, const ScanFilter& filter)
{
    if (filter.rings == RingSource::AzimuthWrap) scan.ring = ringsFromAzimuthWraps(scan.points);
    if (filter.rings == RingSource::None) scan.ring.clear();
    WorldScan w;
    w.deskewed = filter.deskew && !scan.time_s.empty();
    double t0 = 0, t1 = 0;
    if (w.deskewed)
    {
        if (scan.time_absolute)
            for (double& t : scan.time_s) t -= poses.stamp(i);
        const auto [lo, hi] = std::minmax_element(scan.time_s.begin(), scan.time_s.end());
        t0 = *lo, t1 = *hi;
        if (t1 - t0 <= 0) w.deskewed = false;
    }
    // One pose per deskew step (or one for the whole scan).
    const int steps = w.deskewed ? kDeskewSteps : 1;
    std::vector<Eigen::Isometry3f> T_world_lidar(static_cast<size_t>(steps));
    for (int s = 0; s < steps; ++s)
    {
        const double dt = w.deskewed ? t0 + (t1 - t0) * (s + 0.5) / steps : 0.0;
        T_world_lidar[size_t(s)] = poses.T_world_lidar(i, dt).cast<float>();
    }
    const float min2 = float(filter.min_range_m * filter.min_range_m),
                max2 = float(filter.max_range_m * filter.max_range_m);
    w.points.reserve(scan.size());
    w.origins.reserve(scan.size());
    w.intensity.reserve(scan.size());
    w.range_m.reserve(scan.size());
    for (size_t k = 0; k < scan.size(); ++k)
    {
        const Eigen::Vector3f& p = scan.points[k];
        const float r2 = p.squaredNorm();
        if (r2 < min2 || r2 > max2)
        {
            ++w.dropped_by_range;
            continue;
        }
        int s = 0;
        if (w.deskewed) s = std::min(steps - 1, int((scan.time_s[k] - t0) / (t1 - t0) * steps));
        const Eigen::Isometry3f& T = T_world_lidar[size_t(s)];
        w.points.push_back(T * p);
        w.origins.push_back(T.translation());
        w.intensity.push_back(scan.intensity[k]);
        w.range_m.push_back(std::sqrt(r2));
        if (!scan.ring.empty()) w.ring.push_back(scan.ring[k]);
    }
    return w;
}

}  // namespace quasiloc::map
