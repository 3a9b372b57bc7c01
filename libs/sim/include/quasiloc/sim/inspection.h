#pragma once
// A picture for a person checking the simulator: a raw camera frame beside the LiDAR map's reflectivity
// projected at the same pose with the same camera model (distortion included), nearest point per pixel
// (z-buffer, 2x2 splats), so the modality gap and the geometric alignment can be judged at a glance.
#include <mrpt/poses/CPose3D.h>

#include <opencv2/core.hpp>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/map/lidar_map.h>

namespace quasiloc::sim
{
/** CV_8UC1 image of `cam`'s size: reflectivity * 255 of the nearest map point per pixel, 0 where none. */
cv::Mat projectReflectivity(const map::LidarMap& map, const core::CameraModel& cam,
                            const mrpt::poses::CPose3D& T_world_cam, double max_depth_m = 20.0);

/** [camera | projected reflectivity | camera edges over reflectivity], labelled, CV_8UC3. */
cv::Mat makeInspectionImage(const cv::Mat& camera_gray, const cv::Mat& reflectivity_gray);

}  // namespace quasiloc::sim
