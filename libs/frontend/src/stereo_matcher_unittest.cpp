// Stereo: left-right matching along epipolar lines and triangulation. The right image is the left one seen
// through the homography of a known slanted plane, so every pixel's true depth is known.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <quasiloc/frontend/stereo_matcher.h>

#include "test_scenes.h"

using namespace quasiloc;
using namespace quasiloc::frontend;

TEST(Stereo, TriangulatesASlantedPlane)
{
    core::StereoRig rig;
    rig.left = rig.right = test::testCamera();
    const Eigen::Vector3d b(0.11, 0, 0);
    rig.T_left_right = mrpt::poses::CPose3D(b.x(), b.y(), b.z(), 0, 0, 0);
    // Plane n . X_left = dist; the right camera sees X_right = X_left - b = (I - b n^T / dist) X_left.
    const Eigen::Vector3d n = Eigen::Vector3d(0.2, -0.1, 1).normalized();
    const double dist = 2.5;
    Eigen::Matrix3d K;
    K << 420, 0, 319.5, 0, 420, 239.5, 0, 0, 1;
    const Eigen::Matrix3d H = K * (Eigen::Matrix3d::Identity() - b * n.transpose() / dist) * K.inverse();
    const cv::Mat left = test::texturedImage();
    cv::Mat right;
    cv::Matx33d Hcv;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) Hcv(i, j) = H(i, j);
    cv::warpPerspective(left, right, cv::Mat(Hcv), left.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);

    for (const FeatureType type : {FeatureType::Orb, FeatureType::Sift})
    {
        FeatureOptions fo;
        fo.type = type;
        fo.dense_map = false;
        auto ex = createFeatureExtractor(fo);
        Features fl, fr;
        ex->extract(left, cv::Mat(), fl);
        ex->extract(right, cv::Mat(), fr);
        StereoMatcher sm(rig, StereoOptions{});
        EXPECT_NEAR(sm.baseline(), 0.11, 1e-9);
        const auto pts = sm.match(fl, fr);
        ASSERT_GE(pts.size(), 100u) << toString(type);
        size_t good = 0;
        for (const auto& s : pts)
        {
            const cv::Point2f k = fl.keypoints[s.left].pt;
            EXPECT_LE(std::abs(k.y - fr.keypoints[s.right].pt.y), 1.5f + 1e-3f);  // identity rectification
            const double z_true = dist / n.dot(K.inverse() * Eigen::Vector3d(k.x, k.y, 1));
            // Disparity error: ORB keypoints on coarse pyramid levels are localised to ~1-2 px, SIFT's to subpixel.
            const double disp_true = sm.focal() * sm.baseline() / z_true;
            good += std::abs(s.disparity_px - disp_true) < (type == FeatureType::Orb ? 2.0 : 0.5);
            EXPECT_NEAR(s.p_left.z(), sm.focal() * sm.baseline() / s.disparity_px, 1e-6);
            // The point lies on the left keypoint's ray.
            Eigen::Vector2d u;
            ASSERT_TRUE(rig.left.project(s.p_left, u));
            EXPECT_LT(std::hypot(u.x() - k.x, u.y() - k.y), 1e-6);
        }
        std::printf("%s: %zu stereo points, %zu with the true disparity\n", toString(type).c_str(), pts.size(), good);
        EXPECT_GE(good, pts.size() * 9 / 10) << toString(type);
    }
}
