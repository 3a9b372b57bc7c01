#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <Eigen/Core>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/stereo_rig.h>

using quasiloc::core::StereoRig;

namespace
{
StereoRig eurocRig()
{
    const std::string calib = std::string(QUASILOC_SHARED_DIR) + "/data/euroc/calib/";
    return StereoRig::fromEuroc(calib + "cam0_sensor.yaml", calib + "cam1_sensor.yaml");
}

Eigen::Vector2d projectRectified(const cv::Matx33d& R, const cv::Matx34d& P, const Eigen::Vector3d& p_cam)
{
    const cv::Vec3d pr = R * cv::Vec3d(p_cam.x(), p_cam.y(), p_cam.z());
    // Rectified cameras share the left camera's centre after R; P's 4th column carries the baseline.
    const cv::Vec3d h = P.get_minor<3, 3>(0, 0) * pr + cv::Vec3d(P(0, 3), P(1, 3), P(2, 3));
    return {h[0] / h[2], h[1] / h[2]};
}
}  // namespace

TEST(StereoRig, EurocExtrinsicsGiveTheKnownBaseline)
{
    const StereoRig rig = eurocRig();
    EXPECT_NEAR(rig.baseline(), 0.110, 0.002);
    // cam1 is to the right of cam0: +x in the left camera frame.
    EXPECT_GT(rig.T_left_right.x(), 0.10);
    EXPECT_NEAR(rig.T_body_left.x(), -0.0216401454975, 1e-12);
    // T_body_right composed from the parts equals cam1's T_BS.
    const auto T_body_right =
        quasiloc::core::readEurocSensorPose(std::string(QUASILOC_SHARED_DIR) + "/data/euroc/calib/cam1_sensor.yaml");
    EXPECT_LT(quasiloc::core::translationDistance(rig.T_body_right(), T_body_right), 1e-9);
    EXPECT_LT(quasiloc::core::rotationDistanceRad(rig.T_body_right(), T_body_right), 1e-9);
}

TEST(StereoRig, RectificationPutsCorrespondingPointsOnTheSameRow)
{
    const StereoRig rig = eurocRig();
    const auto rect = rig.rectify(0.0);
    EXPECT_NEAR(rect.baseline_m, rig.baseline(), 1e-6);
    const mrpt::poses::CPose3D T_right_left = -rig.T_left_right;
    for (double x : {-1.0, 0.0, 1.2})
        for (double y : {-0.7, 0.3})
            for (double z : {1.5, 4.0, 9.0})
            {
                const Eigen::Vector3d p_left(x, y, z);
                const auto q = T_right_left.composePoint(mrpt::math::TPoint3D(x, y, z));
                const Eigen::Vector2d ul = projectRectified(rect.R_left, rect.P_left, p_left);
                const Eigen::Vector2d ur = projectRectified(rect.R_right, rect.P_right, {q.x, q.y, q.z});
                EXPECT_NEAR(ul.y(), ur.y(), 1e-6);
                // Disparity = f * b / depth along the rectified axis.
                EXPECT_GT(ul.x() - ur.x(), 0);
            }
}

TEST(StereoRig, RectificationMapsUndoDistortion)
{
    const StereoRig rig = eurocRig();
    const auto rect = rig.rectify(0.0);
    // A rectified pixel maps back (through the map) to where the raw camera model sees the same ray.
    for (int v = 60; v < 480; v += 120)
        for (int u = 80; u < 752; u += 150)
        {
            const Eigen::Vector3d ray_rect = rect.rectified_left.unproject({double(u), double(v)});
            const cv::Vec3d r = rect.R_left.t() * cv::Vec3d(ray_rect.x(), ray_rect.y(), ray_rect.z());
            Eigen::Vector2d raw;
            ASSERT_TRUE(rig.left.project({r[0], r[1], r[2]}, raw));
            EXPECT_NEAR(rect.map_left_x.at<float>(v, u), raw.x(), 2e-3);
            EXPECT_NEAR(rect.map_left_y.at<float>(v, u), raw.y(), 2e-3);
        }
}

TEST(StereoRig, RectifyWithFixedPointMapsEqualsTheFloatMaps)
{
    const StereoRig rig = eurocRig();
    const auto rect = rig.rectify(0.0);
    cv::Mat left(480, 752, CV_8UC1), right(480, 752, CV_8UC1);
    cv::randu(left, 0, 256);
    cv::randu(right, 0, 256);
    cv::Mat left_rect, right_rect, left_float, right_float;
    rect.rectify(left, right, left_rect, right_rect);
    cv::remap(left, left_float, rect.map_left_x, rect.map_left_y, cv::INTER_LINEAR);
    cv::remap(right, right_float, rect.map_right_x, rect.map_right_y, cv::INTER_LINEAR);
    EXPECT_EQ(cv::norm(left_rect, left_float, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(right_rect, right_float, cv::NORM_INF), 0.0);
    EXPECT_GT(cv::countNonZero(left_rect), 752 * 480 / 2);
}

TEST(StereoRig, IniRoundTrip)
{
    const StereoRig rig = eurocRig();
    mrpt::config::CConfigFileMemory cfg;
    rig.saveToIni(cfg);
    const StereoRig back = StereoRig::loadFromIni(cfg);
    EXPECT_DOUBLE_EQ(back.left.fx, rig.left.fx);
    EXPECT_DOUBLE_EQ(back.right.dist[1], rig.right.dist[1]);
    EXPECT_LT(quasiloc::core::translationDistance(back.T_left_right, rig.T_left_right), 1e-9);
    EXPECT_LT(quasiloc::core::rotationDistanceRad(back.T_body_left, rig.T_body_left), 1e-9);
}

TEST(StereoRig, BadIniIsRejectedWithTheSectionName)
{
    mrpt::config::CConfigFileMemory cfg;
    eurocRig().saveToIni(cfg);
    cfg.write("camera_rig", "T_left_right", "[0.1 0 0 1 0 0]");
    try
    {
        StereoRig::loadFromIni(cfg);
        FAIL() << "expected InputError";
    }
    catch (const quasiloc::core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("T_left_right"), std::string::npos) << e.what();
    }
}
