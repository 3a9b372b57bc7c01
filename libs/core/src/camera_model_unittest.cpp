#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <opencv2/calib3d.hpp>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/core/error.h>
#include <random>

using quasiloc::core::CameraModel;
using quasiloc::core::DistortionModel;

namespace
{
// EuRoC cam0 (V1_01): radial-tangential.
CameraModel eurocCam0()
{
    CameraModel c = CameraModel::pinhole(752, 480, 458.654, 457.296, 367.215, 248.375);
    c.model = DistortionModel::RadTan;
    c.dist = {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05, 0};
    return c;
}
// A typical fisheye (TUM-VI like) equidistant camera.
CameraModel fisheyeCam()
{
    CameraModel c = CameraModel::pinhole(512, 512, 190.978, 190.973, 254.932, 256.897);
    c.model = DistortionModel::Equidistant;
    c.dist = {0.0034823, 0.000715, -0.0020532, 0.0002029, 0};
    return c;
}
CameraModel radtanWithK3()
{
    CameraModel c = eurocCam0();
    c.dist[4] = 0.01;
    return c;
}

std::vector<Eigen::Vector2d> pixelGrid(const CameraModel& c, int step)
{
    std::vector<Eigen::Vector2d> px;
    for (int v = 0; v < c.height; v += step)
        for (int u = 0; u < c.width; u += step) px.emplace_back(u + 0.25, v + 0.75);
    return px;
}

class AllModels : public ::testing::TestWithParam<int>
{
   protected:
    CameraModel cam() const
    {
        switch (GetParam())
        {
            case 0: return CameraModel::pinhole(640, 480, 500, 505, 320.5, 240.5);
            case 1: return eurocCam0();
            case 2: return radtanWithK3();
            default: return fisheyeCam();
        }
    }
};
}  // namespace

TEST_P(AllModels, UnprojectThenProjectRoundTripsTo1e6Px)
{
    const CameraModel c = cam();
    double worst = 0;
    for (const auto& px : pixelGrid(c, 8))
    {
        const Eigen::Vector3d ray = c.unproject(px);
        for (double depth : {0.3, 2.0, 25.0})
        {
            Eigen::Vector2d back;
            ASSERT_TRUE(c.project(depth * ray, back));
            worst = std::max(worst, (back - px).norm());
        }
    }
    EXPECT_LT(worst, 1e-6) << "model " << GetParam();
}

TEST_P(AllModels, ProjectThenUnprojectGivesTheSameRay)
{
    const CameraModel c = cam();
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> U(-0.6, 0.6);
    for (int i = 0; i < 500; ++i)
    {
        const Eigen::Vector3d p(U(rng), U(rng), 1.0 + std::abs(U(rng)) * 5);
        Eigen::Vector2d px;
        ASSERT_TRUE(c.project(p, px));
        const Eigen::Vector3d b = c.unprojectBearing(px);
        EXPECT_LT((b - p.normalized()).norm(), 1e-9);
    }
}

TEST_P(AllModels, DownscaledCameraSeesEachPointAtTheSamePlaceOfTheCoarserGrid)
{
    const CameraModel c = cam();
    const CameraModel h = c.downscaled(2);
    EXPECT_EQ(h.width, c.width / 2);
    EXPECT_EQ(h.height, c.height / 2);
    for (const auto& px : pixelGrid(c, 16))
    {
        const Eigen::Vector3d p = 3.0 * c.unproject(px);
        if (!p.allFinite()) continue;  // the fisheye's corners lie beyond 90 deg: no point on the plane z = 1
        Eigen::Vector2d u;
        ASSERT_TRUE(h.project(p, u));
        // Pixel centres: full pixel x covers [x - 0.5, x + 0.5), half pixel (x + 0.5) / 2 - 0.5 the same span.
        EXPECT_LT((u - ((px.array() + 0.5) / 2 - 0.5).matrix()).norm(), 1e-9) << "model " << GetParam();
    }
    EXPECT_THROW((void)c.downscaled(0), quasiloc::core::InputError);
    EXPECT_THROW((void)c.downscaled(c.width + 1), quasiloc::core::InputError);
}

TEST(CameraModel, DownscaledOddSizeKeepsTheWholeCoarsePixels)
{
    // A real KITTI camera: 1242x375 pixels.
    const CameraModel c = CameraModel::pinhole(1242, 375, 721.5, 721.5, 609.6, 172.9);
    const CameraModel h = c.downscaled(2);
    EXPECT_EQ(h.width, 621);
    EXPECT_EQ(h.height, 187);
    EXPECT_DOUBLE_EQ(h.fx, 721.5 / 2);
    EXPECT_DOUBLE_EQ(h.cy, (172.9 + 0.5) / 2 - 0.5);
    const CameraModel t = c.downscaled(4);
    EXPECT_EQ(t.width, 310);
    EXPECT_EQ(t.height, 93);
}

TEST_P(AllModels, AnalyticJacobianEqualsNumeric)
{
    const CameraModel c = cam();
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> U(-0.7, 0.7);
    for (int i = 0; i < 200; ++i)
    {
        const Eigen::Vector3d p(U(rng), U(rng), 0.5 + std::abs(U(rng)) * 4);
        Eigen::Vector2d px;
        Eigen::Matrix<double, 2, 3> J;
        ASSERT_TRUE(c.project(p, px, &J));
        Eigen::Matrix<double, 2, 3> Jn;
        const double h = 1e-6;
        for (int k = 0; k < 3; ++k)
        {
            Eigen::Vector3d dp = Eigen::Vector3d::Zero();
            dp[k] = h;
            Eigen::Vector2d a, b;
            c.project(p + dp, a);
            c.project(p - dp, b);
            Jn.col(k) = (a - b) / (2 * h);
        }
        EXPECT_LT((J - Jn).cwiseAbs().maxCoeff(), 1e-4 * (1 + J.cwiseAbs().maxCoeff())) << "point " << p.transpose();
    }
}

TEST_P(AllModels, DistortionJacobianEqualsNumeric)
{
    const CameraModel c = cam();
    for (double x = -0.6; x <= 0.6; x += 0.15)
        for (double y = -0.5; y <= 0.5; y += 0.125)
        {
            Eigen::Matrix2d J, Jn;
            c.distort({x, y}, &J);
            const double h = 1e-7;
            Jn.col(0) = (c.distort({x + h, y}) - c.distort({x - h, y})) / (2 * h);
            Jn.col(1) = (c.distort({x, y + h}) - c.distort({x, y - h})) / (2 * h);
            EXPECT_LT((J - Jn).cwiseAbs().maxCoeff(), 1e-6);
        }
}

INSTANTIATE_TEST_SUITE_P(CameraModels, AllModels, ::testing::Values(0, 1, 2, 3));

TEST(CameraModel, RadTanEqualsOpenCvProjectPoints)
{
    for (const CameraModel& c : {eurocCam0(), radtanWithK3()})
    {
        std::vector<cv::Point3d> pts;
        std::mt19937 rng(1);
        std::uniform_real_distribution<double> U(-0.6, 0.6);
        for (int i = 0; i < 300; ++i) pts.emplace_back(U(rng), U(rng), 1.0 + std::abs(U(rng)) * 3);
        std::vector<cv::Point2d> cv_px;
        cv::projectPoints(pts, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), cv::Mat(c.K()), c.distCoeffs(), cv_px);
        for (size_t i = 0; i < pts.size(); ++i)
        {
            Eigen::Vector2d px;
            ASSERT_TRUE(c.project({pts[i].x, pts[i].y, pts[i].z}, px));
            EXPECT_NEAR(px.x(), cv_px[i].x, 1e-6);
            EXPECT_NEAR(px.y(), cv_px[i].y, 1e-6);
        }
    }
}

TEST(CameraModel, EquidistantEqualsOpenCvFisheyeProjectPoints)
{
    const CameraModel c = fisheyeCam();
    std::vector<cv::Point3d> pts;
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> U(-1.5, 1.5);
    for (int i = 0; i < 300; ++i) pts.emplace_back(U(rng), U(rng), 0.5 + std::abs(U(rng)));
    std::vector<cv::Point2d> cv_px;
    cv::fisheye::projectPoints(pts, cv_px, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), cv::Mat(c.K()), c.distCoeffs());
    for (size_t i = 0; i < pts.size(); ++i)
    {
        Eigen::Vector2d px;
        ASSERT_TRUE(c.project({pts[i].x, pts[i].y, pts[i].z}, px));
        EXPECT_NEAR(px.x(), cv_px[i].x, 1e-6);
        EXPECT_NEAR(px.y(), cv_px[i].y, 1e-6);
    }
}

TEST(CameraModel, PointsBehindTheCameraDoNotProject)
{
    Eigen::Vector2d px;
    EXPECT_FALSE(eurocCam0().project({0.1, 0.2, -1.0}, px));
    EXPECT_FALSE(eurocCam0().project({0.1, 0.2, 0.0}, px));
}

TEST(CameraModel, IniRoundTripUsesTCameraKeys)
{
    for (const CameraModel& c : {eurocCam0(), fisheyeCam(), CameraModel::pinhole(320, 240, 300, 300, 160, 120)})
    {
        mrpt::config::CConfigFileMemory cfg;
        c.saveToIni(cfg, "cam");
        // The keys MRPT's TCamera reads and writes.
        EXPECT_TRUE(cfg.keyExists("cam", "resolution"));
        EXPECT_TRUE(cfg.keyExists("cam", "fx"));
        EXPECT_TRUE(cfg.keyExists("cam", "distortion_model"));
        const CameraModel back = CameraModel::loadFromIni(cfg, "cam");
        EXPECT_EQ(back.model, c.model);
        EXPECT_EQ(back.width, c.width);
        EXPECT_EQ(back.height, c.height);
        EXPECT_DOUBLE_EQ(back.fx, c.fx);
        EXPECT_DOUBLE_EQ(back.cy, c.cy);
        for (int i = 0; i < 5; ++i) EXPECT_NEAR(back.dist[i], c.dist[i], 1e-15);
    }
}

TEST(CameraModel, HandWrittenPlumbBobIniLoads)
{
    mrpt::config::CConfigFileMemory cfg(
        "[cam]\nresolution=[752 480]\ncx=367.215\ncy=248.375\nfx=458.654\nfy=457.296\n"
        "dist=[-0.28340811 0.07395907 0.00019359 1.76187114e-05 0]\ndistortion_model=plumb_bob\n");
    const CameraModel c = CameraModel::loadFromIni(cfg, "cam");
    EXPECT_EQ(c.model, DistortionModel::RadTan);
    EXPECT_DOUBLE_EQ(c.dist[0], -0.28340811);
    EXPECT_EQ(c.width, 752);
}

TEST(CameraModel, LoadsEurocSensorYaml)
{
    const CameraModel c =
        CameraModel::fromEurocYaml(std::string(QUASILOC_SHARED_DIR) + "/data/euroc/calib/cam0_sensor.yaml");
    EXPECT_EQ(c.width, 752);
    EXPECT_EQ(c.height, 480);
    EXPECT_DOUBLE_EQ(c.fx, 458.654);
    EXPECT_DOUBLE_EQ(c.cy, 248.375);
    EXPECT_EQ(c.model, DistortionModel::RadTan);
    EXPECT_DOUBLE_EQ(c.dist[0], -0.28340811);
    EXPECT_DOUBLE_EQ(c.dist[3], 1.76187114e-05);
}

TEST(CameraModel, BadInputNamesTheInput)
{
    try
    {
        CameraModel::fromEurocYaml("/nonexistent/sensor.yaml");
        FAIL() << "expected InputError";
    }
    catch (const quasiloc::core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/sensor.yaml"), std::string::npos);
    }
    mrpt::config::CConfigFileMemory cfg("[cam]\nresolution=[752 480]\ncx=1\ncy=1\nfx=-5\nfy=5\n");
    EXPECT_THROW(CameraModel::loadFromIni(cfg, "cam"), quasiloc::core::InputError);
    EXPECT_THROW(CameraModel::loadFromIni(cfg, "missing_section"), quasiloc::core::InputError);
    EXPECT_THROW(quasiloc::core::distortionModelFromString("weird", "x"), quasiloc::core::InputError);
}
