#pragma once
// StereoCloud: the 3-D points a calibrated stereo pair sees in one frame, in the (raw) left camera frame: the
// query of global localization by geometry (geometric_localizer.h).
//
// Rectify both images (core::StereoRig::rectify), semi-global block matching (cv::StereoSGBM, 3-way), disparity ->
// depth in the rectified left frame, rotated back to the raw left camera frame. Points nearer than min_depth_m or
// farther than max_depth_m are dropped (depth noise grows with depth squared: at 0.11 m baseline and 458 px focal
// length a quarter pixel of disparity is 8 cm at 4 m). The rest are thinned to one point per voxel_m voxel (the
// first in row-major pixel order: deterministic) so that a near wall does not outweigh the rest of the scene, and
// if still above max_points, every k-th is kept.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <quasiloc/core/stereo_rig.h>
#include <cstdint>
#include <string>
#include <vector>

namespace quasiloc::reloc
{
struct StereoCloudOptions
{
    int num_disparities = 64;   ///< SGBM search range (multiple of 16)
    int block_size = 5;         ///< SGBM block (odd)
    int uniqueness_ratio = 10;  ///< SGBM: the best cost must beat the second best by this percentage
    double min_depth_m = 0.3, max_depth_m = 3.5;
    double voxel_m = 0.08;
    int max_points = 2000;
    double disparity_sigma_px = 0.25;  ///< disparity noise: the depth sigma of a point is z^2 / (f b) times this
    /** 1: full resolution; 2: the rectified pair halved before matching (about 4x faster; disparities in
     *  full-resolution pixels either way, num_disparities too). */
    int downscale = 2;

    /** InputError naming `input` and the key for a value that cannot be used. */
    void check(const std::string& input, const std::string& section) const;
};

/** One frame's SGBM disparity, and the rectified pair it was computed on (the tracker searches the right image
 *  for its left keypoints around it: tracking/guided_stereo.h). */
struct StereoDisparity
{
    cv::Mat left_rect, right_rect;  ///< the rectified pair at full resolution, CV_8UC1
    cv::Mat disparity;              ///< CV_16S, 16 x the disparity in pixels of the scaled pair (<= 0: none)
    int scale = 1;  ///< downscale: disparity pixel (x, y) covers full-resolution pixels s x .. s x + s - 1
};

/** A box of voxel indices, [x0, x0 + nx) x [y0, y0 + ny) x [z0, z0 + nz) (empty: nx = 0): where the voxels of
 *  StereoCloud::points can be. */
struct VoxelBox
{
    int64_t x0 = 0, y0 = 0, z0 = 0, nx = 0, ny = 0, nz = 0;
};

class StereoCloud
{
   public:
    StereoCloud(const core::StereoRig& rig, const StereoCloudOptions& options);

    /** Points (left camera frame) of one stereo pair of raw 8-bit images. InputError naming `input` for images
     *  that are empty, not CV_8UC1 or not of the calibrated size. */
    std::vector<Eigen::Vector3f> compute(const cv::Mat& left_raw, const cv::Mat& right_raw,
                                         const std::string& input = "stereo frame") const;
    /** compute()'s two steps: the disparity of the pair (same errors), then its points. */
    StereoDisparity disparity(const cv::Mat& left_raw, const cv::Mat& right_raw,
                              const std::string& input = "stereo frame") const;
    std::vector<Eigen::Vector3f> points(const StereoDisparity& d) const;
    /** The rectification the disparities refer to. */
    const core::StereoRectification& rectification() const { return rect_; }

    /** Depth noise [m] of a point at depth z [m] (disparity_sigma_px through z = f b / d). */
    double depthSigma(double z_m) const
    {
        return z_m * z_m / (rect_.P_left(0, 0) * rect_.baseline_m) * options_.disparity_sigma_px;
    }

   private:
    StereoCloudOptions options_;
    core::StereoRectification rect_;
    cv::Size size_;
    VoxelBox voxels_;  ///< where the points' voxels can be
};

}  // namespace quasiloc::reloc
