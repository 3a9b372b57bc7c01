#pragma once
// QuasiImage: the LiDAR map rendered as an image at a camera pose, in the camera's own pixel geometry
// (whatever model the renderer is given: the raw distorted camera for raw images, a pinhole for rectified
// ones), with per-pixel provenance so every valid pixel lifts to a metric map point.
#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <quasiloc/core/camera_model.h>

namespace quasiloc::quasi
{
/** Counts and wall-clock milliseconds of one render() (the split asked for by the benchmark). */
struct RenderStats
{
    size_t candidate_points = 0;        ///< points in the culled ranges of the VisibilityIndex
    size_t projected_points = 0;        ///< of those, in depth range and inside the image
    size_t splatted_pixels = 0;         ///< empty pixels covered by a point's splat (QuasiOptions::point_size_m)
    size_t sparse_pixels = 0;           ///< pixels won by a point (after the see-through filter)
    size_t occluded_pixels = 0;         ///< pixels dropped by the see-through filter
    size_t completed_pixels = 0;        ///< pixels filled by completion
    size_t scanline_filled_pixels = 0;  ///< pixels filled between scan lines (QuasiOptions::scanline_gap_px)
    double ms_culling = 0, ms_projection = 0, ms_completion = 0, ms_encoding = 0;
    /** CPU time of the whole process during each stage (all threads): the work done, which unlike the wall
     *  time does not grow when other processes compete for the cores. Meaningful when one render runs at a time. */
    double cpu_ms_culling = 0, cpu_ms_projection = 0, cpu_ms_completion = 0, cpu_ms_encoding = 0;
    double msTotal() const { return ms_culling + ms_projection + ms_completion + ms_encoding; }
    double cpuMsTotal() const { return cpu_ms_culling + cpu_ms_projection + cpu_ms_completion + cpu_ms_encoding; }
};

struct QuasiImage
{
    /** Q: H = h(reflectivity), S = s0, V = b1 + b2 * h(depth variation); black where invalid. CV_8UC3 (BGR). */
    cv::Mat bgr;
    /** What the grayscale front-end sees (QuasiOptions::gray_mode); 0 where invalid. CV_8UC1. */
    cv::Mat gray;
    /** Completed camera-z depth in metres; 0 where invalid. CV_32FC1. */
    cv::Mat depth;
    /** Completed map reflectivity in [0, 1] (not normalised); 0 where invalid. CV_32FC1. */
    cv::Mat reflectivity;
    /** 255 where the pixel has a value (sparse or completed), else 0. CV_8UC1. */
    cv::Mat valid;
    /** 255 where a map point projects into the pixel (or, with QuasiOptions::point_size_m, its splat covers it)
     *  and won its z-buffer (a point's own value), else 0. CV_8UC1. */
    cv::Mat sparse;
    /** LidarMap index of the point the pixel shows (-1: none). Sparse pixels: the z-buffer winner.
     *  Completed pixels: the pixel-nearest neighbour that is consistent with the completed value in both
     *  depth and reflectivity; lift through this point (its metric position), not through depth * ray.
     *  CV_32SC1. */
    cv::Mat provenance;

    mrpt::poses::CPose3D T_world_cam;  ///< the pose it was rendered at
    core::CameraModel camera;          ///< the pixel geometry it was rendered in
    RenderStats stats;

    int width() const { return bgr.cols; }
    int height() const { return bgr.rows; }
};

/** Where a keypoint of q can stand and its descriptor be read: pixels a map point won (sparse, with provenance), at
 *  least `margin` from the border, whose (2 margin + 1)^2 neighbourhood is at least min_valid_share valid. CV_8UC1,
 *  255 where it can. */
cv::Mat keypointSupportMask(const QuasiImage& q, int margin, double min_valid_share);

}  // namespace quasiloc::quasi
