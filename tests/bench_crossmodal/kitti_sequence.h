#pragma once
// The real cross-modal test set ../shared/data/kitti_raw_seq78 (see its README): a LiDAR map with
// reflectivity, rectified cam2 query images of the odd frames and their poses T_world_cam2.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/map/lidar_map.h>
#include <string>
#include <vector>

namespace quasiloc::bench
{
struct QueryFrame
{
    std::string name;  ///< e.g. "kitti 0000000001"
    cv::Mat image;     ///< 8-bit, gray or BGR
    Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
};

struct CrossModalSequence
{
    std::string name;
    map::LidarMap map;
    core::CameraModel camera;
    std::vector<QueryFrame> frames;
};

/** Loads the folder: the map (map_path: a LidarMap .map file as map-build or map-import write it, or a cloud
 *  imported like map-import; empty: the folder's map_even_frames_5cm.ply), calib.txt (K_cam2, no distortion),
 *  poses_cam2.txt and image_02/<10-digit frame>.png. At most max_frames queries (0: all), evenly spread.
 *  InputError naming the file for anything missing or malformed. */
CrossModalSequence loadKittiSequence(const std::string& dir, int max_frames, const std::string& map_path = "");

}  // namespace quasiloc::bench
