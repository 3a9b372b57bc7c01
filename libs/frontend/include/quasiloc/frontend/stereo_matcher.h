#pragma once
// Left-right matching along epipolar lines and triangulation of query-side 3D points (the P^C of the
// point-to-plane residual). Keypoints of the raw (distorted) images are mapped into the rectified pair
// (core::StereoRig::rectify); a pair is a candidate when its rectified rows agree within max_epipolar_px and
// its disparity is in range; among candidates, mutual nearest neighbour + ratio test on the descriptors.
//
// Options: [Stereo] (StereoOptions::declare, stereo_matcher.cpp).
#include <Eigen/Core>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/frontend/point_matcher.h>
#include <string>
#include <vector>

namespace quasiloc::frontend
{
struct StereoOptions : public core::DeclaredOptions
{
    double max_epipolar_px = 1.5;
    double min_disparity_px = 1.0;
    double max_disparity_px = 120;
    double ratio = 0.9;
    double max_distance_l2 = 1.0;
    int max_distance_hamming = 80;
    double max_depth_m = 30;

    void declare(core::OptionTable& t) override;
    /** InputError naming `input` and the key for a value out of its declared range, or unless max_disparity_px >
     *  min_disparity_px. */
    void check(const std::string& input) const;
};

struct StereoPoint
{
    int left = -1, right = -1;  ///< keypoint indices
    float disparity_px = 0;     ///< rectified
    float similarity = 0;
    Eigen::Vector3d p_left{0, 0, 0};  ///< in the (raw) left camera frame, metres
};

class StereoMatcher
{
   public:
    /** Rectifies the rig once (InputError for an unusable rig or options). */
    StereoMatcher(const core::StereoRig& rig, const StereoOptions& options);

    std::vector<StereoPoint> match(const Features& left, const Features& right) const;

    /** Raw pixel of the left (cam 0) or right (cam 1) image -> rectified pixel (both with the left principal
     *  point, so u_left - u_right is the disparity). */
    Eigen::Vector2d rectifyPixel(int cam, const cv::Point2f& px) const;
    double baseline() const { return baseline_m_; }
    double focal() const { return f_; }

   private:
    core::StereoRig rig_;
    StereoOptions opt_;
    Eigen::Matrix3d R_rect_raw_[2];
    double f_ = 0, cx_ = 0, cy_ = 0, baseline_m_ = 0;
};

}  // namespace quasiloc::frontend
