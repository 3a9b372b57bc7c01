#pragma once
// Sampling helpers shared by the direct alignment's Levenberg-Marquardt (direct_alignment.cpp) and the window's
// edge factor (direct_factor.cpp), so that both see exactly the same residuals.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/estimation/direct_alignment.h>
#include <vector>

namespace quasiloc::estimation::detail
{
/** The k-th smallest of `values` (0-based, k < size; values in [0, 2^22), such as the squared norms of 3x3 Sobel
 *  derivatives of 8-bit images): the value std::nth_element would put at k, from a histogram of the high bits
 *  (the bucket that holds it) and one of the low bits within that bucket (the camera edge field's percentile). */
int32_t kthSmallest(const std::vector<int32_t>& values, size_t k);

/** Bilinear sample of a CV_32F image at (x, y); the caller guarantees 0 <= x < cols - 1, 0 <= y < rows - 1. */
inline float bilinear(const cv::Mat& m, float x, float y)
{
    const int x0 = int(x), y0 = int(y);
    const float ax = x - float(x0), ay = y - float(y0);
    const float* r0 = m.ptr<float>(y0) + x0;
    const float* r1 = m.ptr<float>(y0 + 1) + x0;
    return (1 - ay) * ((1 - ax) * r0[0] + ax * r0[1]) + ay * ((1 - ax) * r1[0] + ax * r1[1]);
}

/** Inside with a one-pixel border, so that the central differences of the field can be sampled too. Tested on
 *  the FLOAT coordinates the sampler will use: a double just below cols - 2 can round up to cols - 2 as a float,
 *  and the +1 sample would then read past the end of the image (found by AddressSanitizer: the garbage it read
 *  made the tracker's results differ from run to run). */
inline bool insideForBilinear(const cv::Mat& m, float x, float y)
{
    return x >= 1.f && y >= 1.f && x < float(m.cols - 2) && y < float(m.rows - 2);
}

/** Projection of a world point into level `L` of the field: false when behind the camera or outside. */
inline bool projectToLevel(const core::CameraModel& camera, const CameraEdgeLevel& L,
                           const Eigen::Isometry3d& T_cam_world, const Eigen::Vector3d& p_world, Eigen::Vector3d& p_cam,
                           Eigen::Vector2d& u_level, Eigen::Matrix<double, 2, 3>* J_level)
{
    p_cam = T_cam_world * p_world;
    Eigen::Vector2d u;
    if (!camera.project(p_cam, u, J_level, 1e-3)) return false;
    u_level = (u.array() + 0.5) * L.scale - 0.5;
    if (J_level) *J_level *= L.scale;
    return insideForBilinear(L.edges, float(u_level.x()), float(u_level.y()));
}

}  // namespace quasiloc::estimation::detail
