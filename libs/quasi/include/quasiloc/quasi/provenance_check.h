#pragma once
// Checks and pictures of a quasi-image's provenance: every valid pixel's map point reprojected (double
// precision, the camera model of the quasi-image) and compared with the pixel.
#include <opencv2/core.hpp>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/quasi/quasi_image.h>

namespace quasiloc::quasi
{
struct ProvenanceCheck
{
    cv::Mat error_px;  ///< CV_32FC1: distance (px) between each valid pixel and its point's projection; NaN: none
    size_t sparse_pixels = 0, completed_pixels = 0;
    double max_sparse_px = 0, max_completed_px = 0;  ///< Chebyshev (max of |du|, |dv|)
    double mean_sparse_px = 0, mean_completed_px = 0;
};

/** Reprojects the provenance point of every valid pixel of `q` (rendered from `map`). */
ProvenanceCheck checkProvenance(const map::LidarMap& map, const QuasiImage& q);

/** The camera image (gray or BGR) with, on a grid of `step_px`, every valid quasi-image pixel's provenance
 *  point drawn where it reprojects: green within 0.5 px of the pixel (sparse), yellow within
 *  `completion_radius_px` + 0.5 (completed), red beyond (an error). */
cv::Mat drawProvenanceOverlay(const cv::Mat& camera_image, const map::LidarMap& map, const QuasiImage& q,
                              int completion_radius_px, int step_px = 6);

/** camera | quasi (BGR) | overlay side by side, BGR. */
cv::Mat makeTriple(const cv::Mat& camera_image, const QuasiImage& q, const cv::Mat& overlay);

}  // namespace quasiloc::quasi
