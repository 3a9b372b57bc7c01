// Map lines (map_lines.h): a crease and a contour of a rendered depth image lift to the right 3D lines, the shading
// tells an edge from a line on one surface, and the association never leaves its window.
#include <gtest/gtest.h>

#include <quasiloc/tracking/map_lines.h>

#include <random>

using namespace quasiloc;

namespace
{
const core::CameraModel kCamera = core::CameraModel::pinhole(320, 240, 300, 300, 160, 120);

/** Camera-z depth of a scene seen from the identity pose: a wall at z = 3 and, below it, a floor at y = 1 (y down);
 *  with box_u > 0, a box face at z = 2 covers the columns u < box_u. */
cv::Mat renderRoom(int box_u = 0)
{
    cv::Mat depth(kCamera.height, kCamera.width, CV_32FC1);
    for (int v = 0; v < depth.rows; ++v)
        for (int u = 0; u < depth.cols; ++u)
        {
            const double yn = (v - kCamera.cy) / kCamera.fy;
            double z = 3.0;
            if (yn > 0) z = std::min(z, 1.0 / yn);
            if (u < box_u) z = std::min(z, 2.0);
            depth.at<float>(v, u) = float(z);
        }
    return depth;
}

frontend::LineSegment segment(float u0, float v0, float u1, float v1)
{
    frontend::LineSegment s;
    s.p0 = {u0, v0}, s.p1 = {u1, v1};
    return s;
}

/** Distance of p to the 3D line through a with direction d (unit). */
double lineDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& d)
{
    const Eigen::Vector3d w = p - a;
    return (w - w.dot(d) * d).norm();
}

/** A map line whose support projects (identity pose) onto image row v between columns u0 and u1, at depth z. */
tracking::MapLine rowLine(double v, double u0, double u1, double z, int n = 16)
{
    tracking::MapLine m;
    for (int k = 0; k < n; ++k)
    {
        const double u = u0 + (u1 - u0) * k / (n - 1);
        m.support_world.push_back(z * kCamera.unproject(Eigen::Vector2d(u, v)));
    }
    m.point = m.support_world[size_t(n / 2)];
    m.direction = (m.support_world.back() - m.support_world.front()).normalized();
    return m;
}
}  // namespace

TEST(MapLines, ACreaseLiftsToTheWallFloorLine)
{
    tracking::MapLineOptions o;
    tracking::MapLineExtractor x(kCamera, o, frontend::LineOptions{});
    const cv::Mat depth = renderRoom();
    const cv::Mat shading = x.normalShading(depth);
    ASSERT_EQ(shading.rows, kCamera.height / o.shading_step);
    // The crease is at v = cy + fy / 3 = 220; wall above, floor below shade differently.
    const int s = o.shading_step;
    EXPECT_GE(std::abs(int(shading.at<uint8_t>(190 / s, 160 / s)) - int(shading.at<uint8_t>(234 / s, 160 / s))), 16);
    EXPECT_TRUE(x.isEdge(shading, segment(40.f / s, 220.f / s, 280.f / s, 220.f / s)));
    EXPECT_FALSE(x.isEdge(shading, segment(40.f / s, 150.f / s, 280.f / s, 150.f / s)));  // on the wall

    const auto line = x.lift(segment(40, 220, 280, 220), depth, Eigen::Isometry3d::Identity());
    ASSERT_TRUE(line.has_value());
    EXPECT_GE(int(line->support_world.size()), o.min_support);
    for (const auto& p : line->support_world)
        EXPECT_LT(lineDistance(p, Eigen::Vector3d(0, 1, 3), Eigen::Vector3d::UnitX()), 0.01) << p.transpose();
    EXPECT_GT(std::abs(line->direction.x()), 0.999);
}

TEST(MapLines, AContourLiftsToTheForegroundEdgeEvenWhenTheSegmentIsOff)
{
    tracking::MapLineOptions o;
    tracking::MapLineExtractor x(kCamera, o, frontend::LineOptions{});
    const cv::Mat depth = renderRoom(160);  // box face z = 2 left of u = 160, wall z = 3 right of it
    // The segment 2 px inside the background: the lift must still take the box's edge (x = -1/300 * 2 at z = 2).
    const auto line = x.lift(segment(162, 30, 162, 150), depth, Eigen::Isometry3d::Identity());
    ASSERT_TRUE(line.has_value());
    for (const auto& p : line->support_world)
    {
        EXPECT_NEAR(p.z(), 2.0, 1e-3);
        EXPECT_NEAR(p.x(), -2.0 / 300, 1e-3);
    }
    EXPECT_GT(std::abs(line->direction.y()), 0.999);
    // The shading marks the contour (the background's side is dark), so the tracker keeps the segment.
    const cv::Mat shading = x.normalShading(depth);
    EXPECT_TRUE(x.isEdge(shading, segment(161.f / o.shading_step, 30.f / o.shading_step, 161.f / o.shading_step,
                                          150.f / o.shading_step)));
}

TEST(MapLines, AssociationKeepsTheNearLineAndWeighsCandidatesByDistance)
{
    tracking::MapLineOptions o;
    const std::vector<tracking::MapLine> map = {rowLine(121.5, 60, 260, 3.0), rowLine(126, 60, 260, 3.0)};
    const std::vector<frontend::LineSegment> camera = {segment(80, 120, 240, 120)};
    const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();

    auto narrow = tracking::associateMapLines(camera, map, kCamera, I, 3.0, 1.5, o);
    ASSERT_EQ(narrow.size(), 1u);
    ASSERT_EQ(narrow[0].candidates.size(), 1u);  // the line 6 px away is outside the 3 px window
    EXPECT_DOUBLE_EQ(narrow[0].candidates[0].probability, 1.0);
    // Only the support over the camera segment's extent (u in [78, 242]) is kept.
    const size_t n = narrow[0].candidates[0].support_map.size();
    EXPECT_GE(n, 11u);
    EXPECT_LE(n, 14u);
    EXPECT_NEAR(narrow[0].sigma_px, 1.5 * std::sqrt(double(n) / 2), 1e-9);
    EXPECT_NEAR(narrow[0].line_px.head<2>().norm(), 1.0, 1e-6);

    auto wide = tracking::associateMapLines(camera, map, kCamera, I, 9.0, 1.5, o);
    ASSERT_EQ(wide.size(), 1u);
    ASSERT_EQ(wide[0].candidates.size(), 2u);
    EXPECT_GT(wide[0].candidates[0].probability, wide[0].candidates[1].probability);  // nearer first, likelier
    EXPECT_NEAR(wide[0].candidates[0].probability + wide[0].candidates[1].probability, 1.0, 1e-12);

    // Turned 10 deg (beyond max_angle_deg = 5): no candidate. Beside the map line's extent: no overlap, none.
    const std::vector<frontend::LineSegment> turned = {segment(80, 120, 240, 120 + 160 * std::tan(10 * M_PI / 180))};
    EXPECT_TRUE(tracking::associateMapLines(turned, map, kCamera, I, 9.0, 1.5, o).empty());
    const std::vector<frontend::LineSegment> beside = {segment(270, 121, 315, 121)};
    EXPECT_TRUE(tracking::associateMapLines(beside, map, kCamera, I, 9.0, 1.5, o).empty());
}

TEST(MapLines, NoCandidateLiesOutsideItsWindow)
{
    // Random map lines and camera segments in the same image: every candidate's support must project within the
    // window of its camera segment's line (RMS), and at most max_candidates per segment.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> U(0, 1);
    tracking::MapLineOptions o;
    std::vector<tracking::MapLine> map;
    for (int i = 0; i < 60; ++i)
    {
        const double v = 20 + 200 * U(rng), u0 = 10 + 150 * U(rng);
        map.push_back(rowLine(v, u0, u0 + 40 + 100 * U(rng), 1 + 4 * U(rng)));
    }
    std::vector<frontend::LineSegment> camera;
    for (int i = 0; i < 40; ++i)
    {
        const float v = float(20 + 200 * U(rng)), u0 = float(10 + 150 * U(rng)), dv = float(4 * (U(rng) - 0.5));
        camera.push_back(segment(u0, v, u0 + float(30 + 100 * U(rng)), v + dv));
    }
    const double window = 4;
    const auto factors =
        tracking::associateMapLines(camera, map, kCamera, Eigen::Isometry3d::Identity(), window, 1.5, o);
    ASSERT_FALSE(factors.empty());
    for (const auto& f : factors)
    {
        EXPECT_LE(int(f.candidates.size()), o.max_candidates);
        for (const auto& c : f.candidates)
        {
            double e2 = 0;
            for (const auto& P : c.support_map)
            {
                Eigen::Vector2d px;
                ASSERT_TRUE(kCamera.project(P, px));
                e2 += std::pow(f.line_px.dot(px.homogeneous()), 2);
            }
            EXPECT_LE(std::sqrt(e2 / double(c.support_map.size())), window + 1e-9);
        }
    }
}
