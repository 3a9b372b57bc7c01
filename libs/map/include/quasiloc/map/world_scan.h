#pragma once
// A scan in the map frame: each kept point in world coordinates with the sensor position it was measured from
// (the ray's origin), its raw intensity, range and ring. Deskewing: when the scan carries per-point times, each
// point is moved with the LiDAR's pose at its own time (interpolated along the trajectory, at the nearest of
// kDeskewSteps evenly spaced times across the scan: 0.4 ms apart for a 0.1 s sweep); otherwise every point takes
// the pose at the scan's stamp (KITTI .bin stores no per-point time: its scans stay as recorded, skewed by up to
// the distance driven in one sweep).
#include <Eigen/Core>
#include <quasiloc/map/lidar_scan.h>
#include <quasiloc/map/scan_poses.h>
#include <vector>

namespace quasiloc::map
{
constexpr int kDeskewSteps = 256;

struct ScanFilter
{
    double min_range_m = 3.0;  ///< nearer points (the vehicle itself) are dropped
    double max_range_m = 80.0;
    bool deskew = true;  ///< use per-point times where the scan has them
    RingSource rings = RingSource::Field;
};

struct WorldScan
{
    std::vector<Eigen::Vector3f> points;   ///< world frame
    std::vector<Eigen::Vector3f> origins;  ///< the LiDAR's position when the point was measured
    std::vector<float> intensity;          ///< raw
    std::vector<float> range_m;
    std::vector<uint16_t> ring;  ///< empty: none
    bool deskewed = false;
    size_t dropped_by_range = 0;
    size_t size() const { return points.size(); }
};

/** Scan i in the world frame (poses.T_world_lidar), filtered by range. InputError naming the scan when a point's
 *  time has no pose. */
WorldScan toWorld(LidarScan&& scan, const ScanPoses& poses, size_t i, const ScanFilter& filter);

}  // namespace quasiloc::map
