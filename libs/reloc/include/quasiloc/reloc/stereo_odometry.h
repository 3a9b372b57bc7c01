#pragma once
// Frame-to-frame stereo odometry with no map: the camera's own motion between consecutive stereo frames, which joins
// the stereo clouds of a second or so into one query (multi-frame stereo queries, stereo_span.h).
//
// Per frame: ORB keypoints of both raw images, left matched to right along the rectified epipolar lines
// (frontend::StereoMatcher) for their 3-D points. The previous frame's stereo points are then matched to this frame's
// left keypoints (descriptors, mutual nearest neighbour and ratio test) within window_px of where they are predicted:
// their previous pixel, or, given the gyroscope's rotation, the previous bearing turned by it. The motion is the PnP
// (estimation::estimateAbsolutePose, RANSAC and refinement) of those 3-D points in this frame's image. A step is
// refused (not ok, with the reason) with fewer than min_inliers inliers, or when the PnP rotation and the gyroscope's
// differ by more than max_gyro_disagreement_deg: a wrong motion would put the earlier clouds in the wrong place.
#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/estimation/absolute_pose.h>
#include <quasiloc/frontend/features.h>
#include <quasiloc/frontend/stereo_matcher.h>
#include <string>
#include <vector>

namespace quasiloc::reloc
{
struct StereoOdometryOptions
{
    int max_keypoints = 1000;  ///< ORB keypoints per image
    double window_px = 60;     ///< search radius around the predicted pixel
    double ratio = 0.9;        ///< descriptor ratio test
    int max_distance_hamming = 70;
    double max_depth_m = 10;  ///< stereo points farther than this are not used (their depth is too uncertain)
    double max_reproj_error_px = 2.0;
    int min_inliers = 20;
    double max_gyro_disagreement_deg = 2.0;
};

/** The motion from the previous frame to this one. */
struct OdometryStep
{
    bool ok = false;
    std::string reason;                                            ///< why not ok
    Eigen::Isometry3d T_prev_cur = Eigen::Isometry3d::Identity();  ///< this frame's left camera in the previous one's
    int stereo_points = 0, matches = 0, inliers = 0;
    double gyro_disagreement_deg = NAN;  ///< NaN: no gyroscope rotation given
    double ms = 0;                       ///< wall time of the step (features, stereo, matching, PnP)
};

class StereoOdometry
{
   public:
    StereoOdometry(const core::StereoRig& rig, const StereoOdometryOptions& options = {});
    ~StereoOdometry();

    /** Feeds the next raw stereo pair; R_prev_cur: the left camera's rotation since the previous frame from the
     *  gyroscope, if any (a prior for the search and a check on the answer). The first frame, or the frame after
     *  reset(), gives a step that is not ok ("no previous frame"). */
    OdometryStep track(const cv::Mat& left_raw, const cv::Mat& right_raw,
                       const std::optional<Eigen::Matrix3d>& R_prev_cur = std::nullopt);
    /** Forgets the previous frame (the next one starts a new chain). */
    void reset() { previous_.reset(); }

   private:
    struct Frame
    {
        frontend::Features left;
        std::vector<int> stereo_left;           ///< left keypoint index of each stereo point
        std::vector<Eigen::Vector3d> stereo_p;  ///< its point, left camera frame
    };

    core::StereoRig rig_;
    StereoOdometryOptions options_;
    std::unique_ptr<frontend::FeatureExtractor> extractor_;
    frontend::StereoMatcher stereo_;
    std::unique_ptr<Frame> previous_;
};

/** The left camera's rotation between two frames from gyroscope samples (body frame, rad/s) taken at times
 *  (t_prev, t_cur], integrated at their rates (each held from the sample before it, t_prev for the first, the last also
 * until t_cur). R_cam_body: rotation of the body frame into the camera frame. */
Eigen::Matrix3d gyroRotation(const std::vector<double>& t, const std::vector<Eigen::Vector3d>& gyro, double t_prev,
                             double t_cur, const Eigen::Matrix3d& R_cam_body);

}  // namespace quasiloc::reloc
