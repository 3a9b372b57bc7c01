#pragma once
// Every pixel's ray of a camera model, tabulated once: the map-line shading and the map-plane fits lift thousands
// of quasi-image pixels per frame (depth * ray), and CameraModel::unproject inverts the distortion iteratively.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <quasiloc/core/camera_model.h>

namespace quasiloc::tracking
{
struct PixelRays
{
    explicit PixelRays(const core::CameraModel& camera);
    /** The point on the normalised plane z = 1 seen by pixel (u, v): depth * ray(u, v) is the camera-frame point. */
    Eigen::Vector3d ray(int u, int v) const { return {double(x.at<float>(v, u)), double(y.at<float>(v, u)), 1.0}; }

    cv::Mat x, y;  ///< CV_32F, camera size: x and y of the ray
};
}  // namespace quasiloc::tracking
