// Stereo odometry on the simulated room: two rendered stereo frames with a known motion between them give that motion
// back; a gyroscope rotation that disagrees is refused; the first frame has no motion. gyroRotation integrates a
// constant rate.
#include <gtest/gtest.h>

#include <quasiloc/core/pose.h>
#include <quasiloc/reloc/stereo_odometry.h>
#include <quasiloc/reloc/view_sampling.h>
#include <quasiloc/sim/stereo_renderer.h>

#include "test_room.h"

using namespace quasiloc;

namespace
{
const std::string kShared = QUASILOC_SHARED_DIR;

struct Fixture
{
    sim::World world;
    core::StereoRig rig;
};

const Fixture& fixture()
{
    static const Fixture f = [] {
        Fixture f;
        f.world = reloc::test::testRoom(kShared);
        const std::string calib = kShared + "/data/euroc/calib/";
        f.rig = core::StereoRig::fromEuroc(calib + "cam0_sensor.yaml", calib + "cam1_sensor.yaml");
        return f;
    }();
    return f;
}

void render(const Eigen::Isometry3d& T_world_cam, uint64_t index, cv::Mat& left, cv::Mat& right)
{
    sim::StereoRenderer renderer(fixture().world, fixture().rig, sim::AppearanceOptions(), 7);
    renderer.render({core::fromIsometry(T_world_cam)}, 0.05 * double(index), index, left, right);
}

/** A camera in the room looking at its clutter, and the motion of one 20 Hz frame of a brisk hand-held walk. */
Eigen::Isometry3d firstPose()
{
    return core::toIsometry(reloc::viewPose(-0.6, 0.3, 1.25, 35 * M_PI / 180, -18 * M_PI / 180));
}
Eigen::Isometry3d motion()
{
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(3 * M_PI / 180, Eigen::Vector3d(0.2, 1, 0.1).normalized()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(0.04, -0.01, 0.05);
    return T;
}
}  // namespace

TEST(StereoOdometry, RecoversAKnownMotionBetweenRenderedFrames)
{
    cv::Mat l0, r0, l1, r1;
    render(firstPose(), 0, l0, r0);
    render(firstPose() * motion(), 1, l1, r1);
    reloc::StereoOdometry odometry(fixture().rig);
    const reloc::OdometryStep first = odometry.track(l0, r0);
    EXPECT_FALSE(first.ok);
    EXPECT_EQ(first.reason, "no previous frame");
    EXPECT_GT(first.stereo_points, 100);

    const reloc::OdometryStep step = odometry.track(l1, r1);
    ASSERT_TRUE(step.ok) << step.reason;
    EXPECT_GT(step.inliers, 50);
    EXPECT_LT(core::translationDistance(step.T_prev_cur, motion()), 0.01) << step.T_prev_cur.translation().transpose();
    EXPECT_LT(core::rotationDistanceRad(step.T_prev_cur, motion()) * 180 / M_PI, 0.2);
}

TEST(StereoOdometry, TheGyroscopePredictsTheSearchAndRefusesADisagreeingMotion)
{
    cv::Mat l0, r0, l1, r1;
    render(firstPose(), 0, l0, r0);
    render(firstPose() * motion(), 1, l1, r1);
    {
        reloc::StereoOdometry odometry(fixture().rig);
        odometry.track(l0, r0);
        const reloc::OdometryStep step = odometry.track(l1, r1, motion().linear());
        ASSERT_TRUE(step.ok) << step.reason;
        EXPECT_LT(step.gyro_disagreement_deg, 0.2);
    }
    {
        // A gyroscope that saw 6 deg more about the vertical: the image motion is 3 deg, so the step is refused.
        reloc::StereoOdometry odometry(fixture().rig);
        odometry.track(l0, r0);
        const Eigen::Matrix3d wrong = motion().linear() * Eigen::AngleAxisd(6 * M_PI / 180, Eigen::Vector3d::UnitY());
        const reloc::OdometryStep step = odometry.track(l1, r1, wrong);
        EXPECT_FALSE(step.ok);
        EXPECT_NE(step.reason.find("gyroscope"), std::string::npos) << step.reason;
    }
    {
        // After reset() the next frame starts a new chain.
        reloc::StereoOdometry odometry(fixture().rig);
        odometry.track(l0, r0);
        odometry.reset();
        EXPECT_EQ(odometry.track(l1, r1).reason, "no previous frame");
    }
}

TEST(StereoOdometry, GyroRotationIntegratesTheRatesInTheCameraFrame)
{
    // 0.5 rad/s about the body's x for 0.1 s (samples at 200 Hz), a camera whose z is the body's x.
    std::vector<double> t;
    std::vector<Eigen::Vector3d> w;
    for (int i = 1; i <= 20; ++i)
    {
        t.push_back(10 + 0.005 * i);
        w.emplace_back(0.5, 0, 0);
    }
    t.push_back(10.2);  // after t_cur: not used
    w.emplace_back(50, 0, 0);
    Eigen::Matrix3d R_cam_body;
    R_cam_body << 0, 1, 0, 0, 0, 1, 1, 0, 0;
    const Eigen::Matrix3d R = reloc::gyroRotation(t, w, 10.0, 10.1, R_cam_body);
    const Eigen::AngleAxisd aa(R);
    EXPECT_NEAR(aa.angle(), 0.05, 1e-9);
    EXPECT_NEAR(std::abs(aa.axis().z()), 1.0, 1e-9);
}
