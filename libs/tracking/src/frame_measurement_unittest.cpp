// predictedKeypoints: where the temporal matching of temporal_predicted_window looks for each previous keypoint
// after a car-like step of 1 m forward with a small turn.
#include <gtest/gtest.h>

#include <cmath>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/tracking/frame_measurement.h>

using namespace quasiloc;

namespace
{
const core::CameraModel kCamera = core::CameraModel::pinhole(1242, 375, 721.5, 721.5, 609.6, 172.9);

Eigen::Vector2d project(const Eigen::Vector3d& p)
{
    Eigen::Vector2d px;
    EXPECT_TRUE(kCamera.project(p, px));
    return px;
}

// Keypoint 0: a stereo point 6 m ahead on the road; 1: a stereo point 25 m ahead on a facade; 2: no stereo point.
tracking::FrameMeasurement previousFrame(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector2d& far_px)
{
    tracking::FrameMeasurement m;
    for (const Eigen::Vector3d& p : points)
    {
        const Eigen::Vector2d px = project(p);
        m.left.points.keypoints.emplace_back(float(px.x()), float(px.y()), 31.f);
        frontend::StereoPoint s;
        s.left = int(m.stereo.size());
        s.p_left = p;
        m.stereo_of_left.push_back(int(m.stereo.size()));
        m.stereo.push_back(s);
    }
    m.left.points.keypoints.emplace_back(float(far_px.x()), float(far_px.y()), 31.f);
    m.stereo_of_left.push_back(-1);
    return m;
}
}  // namespace

TEST(PredictedKeypoints, StereoPointsMoveWithTheirDepthOthersWithTheRotation)
{
    const std::vector<Eigen::Vector3d> points{{-1.0, 1.65, 6.0}, {4.0, -2.0, 25.0}};
    const Eigen::Vector2d far_px(900, 120);
    const tracking::FrameMeasurement previous = previousFrame(points, far_px);
    // The camera moves 1 m forward (z) and turns 2 degrees about its vertical (y) axis.
    Eigen::Isometry3d T_prevcam_cam = Eigen::Isometry3d::Identity();
    T_prevcam_cam.linear() = Eigen::AngleAxisd(2.0 * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
    T_prevcam_cam.translation() = Eigen::Vector3d(0, 0, 1.0);
    const Eigen::Isometry3d T_cam_prevcam = T_prevcam_cam.inverse();

    const std::vector<cv::Point2f> centers = tracking::predictedKeypoints(previous, kCamera, T_cam_prevcam);
    ASSERT_EQ(centers.size(), 3u);
    for (size_t i = 0; i < points.size(); ++i)
    {
        const Eigen::Vector2d expected = project(T_cam_prevcam * points[i]);
        EXPECT_NEAR(centers[i].x, expected.x(), 1e-3) << i;
        EXPECT_NEAR(centers[i].y, expected.y(), 1e-3) << i;
    }
    // The road point 6 m ahead moves far beyond the default 60 px window; the prediction follows it.
    const Eigen::Vector2d before = project(points[0]);
    EXPECT_GT(std::hypot(centers[0].x - before.x(), centers[0].y - before.y()), 60.0);
    // Without depth: the direction rotated (a point at infinity), the translation ignored.
    const Eigen::Vector2d rotated = project(T_cam_prevcam.linear() * kCamera.unproject(far_px));
    EXPECT_NEAR(centers[2].x, rotated.x(), 1e-3);
    EXPECT_NEAR(centers[2].y, rotated.y(), 1e-3);
    EXPECT_GT(std::abs(centers[2].x - far_px.x()), 20.0);  // 2 degrees at fx 721.5: about 25 px
}

TEST(PredictedKeypoints, APointBehindTheCameraKeepsItsDirection)
{
    // A stereo point 0.5 m ahead that the camera passes (1 m forward): it is behind the new camera, so its centre
    // is the rotation-only prediction (the keypoint itself, without rotation).
    const tracking::FrameMeasurement previous = previousFrame({{0.2, 0.3, 0.5}}, Eigen::Vector2d(100, 100));
    Eigen::Isometry3d T_cam_prevcam = Eigen::Isometry3d::Identity();
    T_cam_prevcam.translation() = Eigen::Vector3d(0, 0, -1.0);
    const std::vector<cv::Point2f> centers = tracking::predictedKeypoints(previous, kCamera, T_cam_prevcam);
    const cv::Point2f& k = previous.left.points.keypoints[0].pt;
    EXPECT_NEAR(centers[0].x, k.x, 1e-3);
    EXPECT_NEAR(centers[0].y, k.y, 1e-3);
}
