// Map points (map_points.h): a quasi-image keypoint lifts to the map point it shows and is associated with the camera
// keypoint that carries its descriptor near its projection, never with one outside the window.
#include <gtest/gtest.h>

#include <quasiloc/quasi/quasi_renderer.h>
#include <quasiloc/tracking/map_points.h>

#include <random>

using namespace quasiloc;

namespace
{
const core::CameraModel kCamera = core::CameraModel::pinhole(320, 240, 300, 300, 160, 120);

cv::Mat randomDescriptor(std::mt19937& rng)
{
    cv::Mat d(1, 32, CV_8UC1);
    for (int i = 0; i < 32; ++i) d.at<uint8_t>(0, i) = uint8_t(rng() & 0xff);
    return d;
}

void addKeypoint(frontend::Features& f, float x, float y, const cv::Mat& descriptor)
{
    f.keypoints.emplace_back(cv::Point2f(x, y), 7.f);
    f.descriptors.push_back(descriptor);
}
}  // namespace

TEST(MapPoints, AssociatesWithinTheWindowOnlyAndLiftsThroughProvenance)
{
    // A dense wall at z = 3 m (1 cm grid), rendered at the identity pose.
    map::LidarMap wall;
    for (int r = 0; r < 200; ++r)
        for (int c = 0; c < 300; ++c) wall.addPoint(float(-1.5 + c * 0.01), float(-1.0 + r * 0.01), 3.0f, 0.5f);
    quasi::QuasiRenderer renderer(wall, quasi::QuasiOptions{});
    quasi::QuasiImage q;
    renderer.render(mrpt::poses::CPose3D(), kCamera, q);

    // Quasi-image keypoints with random descriptors; in the camera image: the same descriptors 1.5 px from where
    // the true pose projects their map points (inside a 3 px window) for the first half, and 6 px away (outside)
    // for the second half, plus unrelated keypoints.
    std::mt19937 rng(5);
    frontend::Features quasi_features, camera_features;
    const Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
    const int n = 20;
    for (int i = 0; i < n; ++i)
    {
        const float x = 60.f + 10.f * float(i), y = 80.f + 4.f * float(i);
        const cv::Mat d = randomDescriptor(rng);
        addKeypoint(quasi_features, x, y, d);
        addKeypoint(camera_features, x + (i < n / 2 ? 1.5f : 6.f), y, d);
        addKeypoint(camera_features, x - 20.f, y + 30.f, randomDescriptor(rng));
    }
    tracking::MapPointOptions o;
    o.window_px = 3;
    frontend::PointMatchingOptions matching;
    const auto matches =
        tracking::associateMapPoints(camera_features, quasi_features, q, wall, kCamera, T_world_cam, matching, o);
    ASSERT_EQ(int(matches.size()), n / 2);
    for (const auto& m : matches)
    {
        // The map point is on the wall and projects within the window of its camera pixel.
        EXPECT_NEAR(m.p_map.z(), 3.0, 1e-4);
        Eigen::Vector2d u;
        ASSERT_TRUE(kCamera.project(m.p_map, u));
        EXPECT_LE((u - m.px).norm(), o.window_px);
        EXPECT_DOUBLE_EQ(m.sigma_px, o.sigma_px);
    }
    // A pose 0.1 m to the side moves every projection ~10 px: nothing is associated any more.
    Eigen::Isometry3d T_off = Eigen::Isometry3d::Identity();
    T_off.translation().x() = 0.1;
    EXPECT_TRUE(
        tracking::associateMapPoints(camera_features, quasi_features, q, wall, kCamera, T_off, matching, o).empty());
}
