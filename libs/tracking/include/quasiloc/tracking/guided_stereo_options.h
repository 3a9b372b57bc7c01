#pragma once
// The guided stereo matching's options ([Tracking] guided_* keys; guided_stereo.h).

namespace quasiloc::tracking
{
struct GuidedStereoOptions
{
    int patch_radius_px = 4;           ///< the compared patches are (2 r + 1)^2 pixels of the rectified pair
    int search_px = 3;                 ///< columns searched on each side of the SGBM's disparity (full resolution)
    double max_prior_spread_px = 2.0;  ///< SGBM disparities around the keypoint that differ more: a depth edge
    double max_mean_abs_diff = 6.0;    ///< mean |left - right| per pixel, each patch's mean removed (gray levels)
};
}  // namespace quasiloc::tracking
