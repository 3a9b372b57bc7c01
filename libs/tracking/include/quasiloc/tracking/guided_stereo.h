#pragma once
// GuidedStereo: the right image's match of each left keypoint, searched around the frame's dense (SGBM) disparity
// instead of among the right image's own features (Tracking.stereo_matching = guided).
//
// The frame computes the dense disparity anyway (the surface factor's cloud, stereo_map_points = dense), so the
// right image needs no feature detection: each left keypoint is mapped into the rectified pair, the SGBM disparity
// around it (at the SGBM's reduced resolution) gives the right column to within about a pixel, and a patch
// comparison along the rectified row at full resolution, with a parabola through the best three columns, gives the
// sub-pixel disparity (as ORB-SLAM's stereo search does around a descriptor match). A keypoint whose SGBM
// neighbourhood has no disparity, or disparities that disagree (a depth edge), or whose best column lies at the
// border of the search, or whose patches differ too much, gets no stereo point.
#include <opencv2/core.hpp>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/frontend/stereo_matcher.h>
#include <quasiloc/reloc/stereo_cloud.h>
#include <quasiloc/tracking/guided_stereo_options.h>
#include <vector>

namespace quasiloc::tracking
{
class GuidedStereo
{
   public:
    /** `rect` must be the rectification of the disparities given to match() (reloc::StereoCloud::rectification);
     *  `stereo` gives the disparity and depth ranges, as for the descriptor matching. */
    GuidedStereo(const core::StereoRig& rig, const core::StereoRectification& rect,
                 const frontend::StereoOptions& stereo, const GuidedStereoOptions& options = {});

    /** Stereo points of the `left` keypoints (raw left image). `right` receives one keypoint per point, its pixel
     *  in the raw right image (StereoPoint::right indexes it; size, angle and octave are the left keypoint's). */
    std::vector<frontend::StereoPoint> match(const std::vector<cv::KeyPoint>& left, const reloc::StereoDisparity& d,
                                             std::vector<cv::KeyPoint>& right) const;

   private:
    /** The SGBM disparity [full-resolution px] at rectified pixel (u, v): bilinear over its four scaled neighbours,
     *  all valid and within max_prior_spread_px of each other; <= 0 when there is none. */
    double priorDisparity(const reloc::StereoDisparity& d, double u, double v) const;
    /** The column of the right rectified image that best matches the left patch at (ul, vl) around column
     *  `centre` (sub-pixel); NAN when there is no acceptable one. */
    double searchRow(const cv::Mat& left, const cv::Mat& right, int ul, int vl, int centre) const;

    core::StereoRig rig_;
    frontend::StereoOptions stereo_;
    GuidedStereoOptions opt_;
    Eigen::Matrix3d R_rect_raw_[2];
    double f_ = 0, cx_ = 0, cy_ = 0, cx_right_ = 0, baseline_m_ = 0;
};

}  // namespace quasiloc::tracking
