// GuidedStereo against the descriptor matching on a rendered stereo pair of the simulated room: its points lie
// on the room's surfaces at least as closely, they are as many, and its right keypoints are where the points
// project in the right camera.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/frontend/frontend.h>
#include <quasiloc/map/distance_field.h>
#include <quasiloc/reloc/stereo_cloud.h>
#include <quasiloc/reloc/view_sampling.h>
#include <quasiloc/sim/stereo_renderer.h>
#include <quasiloc/tracking/guided_stereo.h>

// The reloc tests' simulated room and its LiDAR survey (one definition for both libraries' tests).
#include "../../reloc/src/test_room.h"

using namespace quasiloc;

namespace
{
const std::string kShared = QUASILOC_SHARED_DIR;

struct Scene
{
    sim::World world;
    map::DistanceField field;
    core::StereoRig rig;
};

const Scene& scene()
{
    static const Scene s = [] {
        sim::World world = reloc::test::testRoom(kShared);
        const map::LidarMap map = reloc::test::testRoomMap(world);
        map::DistanceFieldOptions fo;
        fo.voxel_m = 0.02;
        const std::string calib = kShared + "/data/euroc/calib/";
        return Scene{std::move(world), map::DistanceField::build(map, fo),
                     core::StereoRig::fromEuroc(calib + "cam0_sensor.yaml", calib + "cam1_sensor.yaml")};
    }();
    return s;
}

struct Pair
{
    cv::Mat left, right;
    Eigen::Isometry3d T_world_cam;
};

Pair renderPair(double heading_deg)
{
    const Scene& s = scene();
    Pair p;
    p.T_world_cam = core::toIsometry(reloc::viewPose(-0.6, 0.3, 1.25, heading_deg * M_PI / 180, -18 * M_PI / 180));
    sim::StereoRenderer renderer(s.world, s.rig, sim::AppearanceOptions(), 7);
    renderer.render({core::fromIsometry(p.T_world_cam)}, 0.0, 0, p.left, p.right);
    return p;
}

/** Median distance [m] of the points (left camera frame) to the map's surfaces, within 4 m depth. */
double medianSurfaceDistance(const std::vector<frontend::StereoPoint>& points, const Eigen::Isometry3d& T_world_cam)
{
    std::vector<double> d;
    for (const auto& p : points)
        if (p.p_left.z() < 4.0) d.push_back(scene().field.distance((T_world_cam * p.p_left).cast<float>()));
    if (d.empty()) return NAN;
    std::nth_element(d.begin(), d.begin() + long(d.size() / 2), d.end());
    return d[d.size() / 2];
}

frontend::FrontendOptions frontendOptions()
{
    frontend::FrontendOptions o;
    o.features.orb_levels = 4;  // the tracker's (config.ini)
    return o;
}
}  // namespace

TEST(GuidedStereo, PointsLieOnTheSurfacesAsCloselyAsDescriptorMatches)
{
    const Scene& s = scene();
    frontend::Frontend left_fe(frontendOptions()), right_fe(frontendOptions());
    const reloc::StereoCloud cloud(s.rig, reloc::StereoCloudOptions{});
    const tracking::GuidedStereo guided(s.rig, cloud.rectification(), frontendOptions().stereo);
    const frontend::StereoMatcher descriptors(s.rig, frontendOptions().stereo);
    for (const double heading : {35.0, 120.0, 250.0})
    {
        const Pair p = renderPair(heading);
        frontend::FrameFeatures L, R;
        left_fe.extractPoints(p.left, cv::Mat(), L);
        right_fe.extractPoints(p.right, cv::Mat(), R);
        const auto by_descriptors = descriptors.match(L.points, R.points);
        std::vector<cv::KeyPoint> right_keypoints;
        const auto by_guide = guided.match(L.points.keypoints, cloud.disparity(p.left, p.right), right_keypoints);
        const double d_desc = medianSurfaceDistance(by_descriptors, p.T_world_cam);
        const double d_guide = medianSurfaceDistance(by_guide, p.T_world_cam);
        std::cout << "heading " << heading << " deg: descriptors " << by_descriptors.size() << " points, median "
                  << d_desc * 100 << " cm from the surfaces; guided " << by_guide.size() << " points, " << d_guide * 100
                  << " cm\n";
        EXPECT_GE(by_guide.size(), by_descriptors.size() * 8 / 10);
        EXPECT_LE(d_guide, std::max(1.2 * d_desc, 0.005));
        ASSERT_EQ(right_keypoints.size(), by_guide.size());
        // Each right keypoint is its point's projection in the right camera.
        const Eigen::Isometry3d T_right_left = core::toIsometry(s.rig.T_left_right).inverse();
        for (const auto& sp : by_guide)
        {
            Eigen::Vector2d px;
            ASSERT_TRUE(s.rig.right.project(T_right_left * sp.p_left, px));
            const cv::Point2f& k = right_keypoints[size_t(sp.right)].pt;
            EXPECT_LT(std::hypot(px.x() - k.x, px.y() - k.y), 0.05);
            EXPECT_EQ(L.points.keypoints[size_t(sp.left)].octave, right_keypoints[size_t(sp.right)].octave);
        }
    }
}

TEST(GuidedStereo, ABlackRightImageGivesNoPoints)
{
    const Scene& s = scene();
    frontend::Frontend fe(frontendOptions());
    const reloc::StereoCloud cloud(s.rig, reloc::StereoCloudOptions{});
    const tracking::GuidedStereo guided(s.rig, cloud.rectification(), frontendOptions().stereo);
    const Pair p = renderPair(35.0);
    frontend::FrameFeatures L;
    fe.extractPoints(p.left, cv::Mat(), L);
    ASSERT_GT(L.points.keypoints.size(), 100u);
    std::vector<cv::KeyPoint> right_keypoints;
    const cv::Mat black(p.right.size(), CV_8UC1, cv::Scalar(0));
    EXPECT_TRUE(guided.match(L.points.keypoints, cloud.disparity(p.left, black), right_keypoints).empty());
    EXPECT_TRUE(right_keypoints.empty());
}

TEST(GuidedStereo, NoDisparityIsAnError)
{
    const Scene& s = scene();
    const reloc::StereoCloud cloud(s.rig, reloc::StereoCloudOptions{});
    const tracking::GuidedStereo guided(s.rig, cloud.rectification(), frontendOptions().stereo);
    std::vector<cv::KeyPoint> right;
    EXPECT_THROW(guided.match({cv::KeyPoint(100, 100, 7)}, reloc::StereoDisparity{}, right), core::InputError);
}
