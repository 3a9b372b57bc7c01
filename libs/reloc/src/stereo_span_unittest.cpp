// StereoSpan: the clouds of linked frames land in the newest camera where a known motion puts them; a refused link
// ends the chain; the newest frame's points win their voxels; frames without clouds carry the motion only.
#include <gtest/gtest.h>

#include <quasiloc/reloc/stereo_span.h>

using namespace quasiloc;

namespace
{
Eigen::Isometry3d step(double forward_m, double yaw_deg)
{
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(0, 0, forward_m);
    return T;
}

/** A world point seen from camera pose T_world_cam, as a one-point cloud in that camera. */
std::vector<Eigen::Vector3f> seen(const Eigen::Isometry3d& T_world_cam, const Eigen::Vector3d& p_world)
{
    return {(T_world_cam.inverse() * p_world).cast<float>()};
}
}  // namespace

TEST(StereoSpan, JoinsLinkedFramesInTheNewestCamera)
{
    // Three frames moving 0.1 m forward and turning 5 deg per frame; each sees a different world point.
    const Eigen::Vector3d a(1, 0, 3), b(-1, 0.5, 2), c(0, -0.5, 4);
    const Eigen::Isometry3d T0 = Eigen::Isometry3d::Identity(), T1 = T0 * step(0.1, 5), T2 = T1 * step(0.1, 5);
    reloc::StereoSpan span(3);
    span.add({0.0, seen(T0, a), {}, false});
    span.add({0.05, seen(T1, b), {}, true, step(0.1, 5)});
    span.add({0.10, seen(T2, c), seen(T2, c), true, step(0.1, 5)});
    const reloc::JoinedClouds j = span.join(0.01, 0, 0);
    EXPECT_EQ(j.frames, 3);
    EXPECT_NEAR(j.span_s, 0.1, 1e-12);
    EXPECT_NEAR(j.path_m, 0.2, 1e-12);
    ASSERT_EQ(j.points.size(), 3u);
    // Newest first; all in the newest camera: back in the world through T2 they are the world points.
    EXPECT_LT((T2 * j.points[0].cast<double>() - c).norm(), 1e-5);
    EXPECT_LT((T2 * j.points[1].cast<double>() - b).norm(), 1e-5);
    EXPECT_LT((T2 * j.points[2].cast<double>() - a).norm(), 1e-5);
    EXPECT_EQ(j.place_points.size(), 1u);
    EXPECT_NEAR(j.oldest_t, 0.0, 1e-12);
    EXPECT_TRUE(j.T_newest_oldest.isApprox(T2.inverse() * T0, 1e-9));
}

TEST(StereoSpan, ARefusedLinkEndsTheChainAndOldFramesDrop)
{
    const Eigen::Vector3d a(1, 0, 3);
    reloc::StereoSpan span(3);
    span.add({0.0, seen(Eigen::Isometry3d::Identity(), a), {}, false});
    span.add({0.1, {Eigen::Vector3f(0, 0, 1)}, {}, false});  // the odometry refused this link
    span.add({0.2, {Eigen::Vector3f(0, 0, 2)}, {}, true, step(0.1, 0)});
    reloc::JoinedClouds j = span.join(0.01, 0, 0);
    EXPECT_EQ(j.frames, 2);
    EXPECT_EQ(j.points.size(), 2u);
    // A fourth frame pushes out the first; frames without clouds carry the motion only.
    reloc::SpanFrame motion_only{0.3, {}, {}, true, step(0.1, 0)};
    motion_only.has_clouds = false;
    span.add(motion_only);
    span.add({0.4, {Eigen::Vector3f(0, 0, 3)}, {}, true, step(0.1, 0)});
    EXPECT_EQ(span.size(), 3u);
    j = span.join(0.01, 0, 0);
    EXPECT_EQ(j.frames, 2);
    EXPECT_EQ(j.linked_frames, 3);
    ASSERT_EQ(j.points.size(), 2u);
    EXPECT_NEAR(j.points[1].z(), 2 - 0.2, 1e-6);  // the frame at 0.2 s, 0.2 m behind the newest
    EXPECT_NEAR(j.path_m, 0.2, 1e-12);
}

TEST(StereoSpan, TheNewestPointsWinTheirVoxelsThenEveryKth)
{
    const std::vector<Eigen::Vector3f> newest{{0.01f, 0, 1}}, older{{0.02f, 0, 1}, {0.5f, 0, 1}};
    const std::vector<Eigen::Vector3f> joined =
        reloc::joinClouds({&newest, &older}, {Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity()}, 0.08, 0);
    ASSERT_EQ(joined.size(), 2u);
    EXPECT_EQ(joined[0], newest[0]);
    EXPECT_EQ(joined[1], older[1]);
    std::vector<Eigen::Vector3f> many;
    for (int i = 0; i < 100; ++i) many.emplace_back(float(i), 0, 1);
    EXPECT_EQ(reloc::joinClouds({&many}, {Eigen::Isometry3d::Identity()}, 0.08, 30).size(), 25u);  // every 4th
}
