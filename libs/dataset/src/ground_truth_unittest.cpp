#include <gtest/gtest.h>

#include <fstream>
#include <quasiloc/core/pose.h>
#include <quasiloc/dataset/ground_truth.h>

#include "test_helpers.h"

using namespace quasiloc;
using namespace quasiloc::dataset;
using quasiloc::dataset::test::TempDir;

TEST(GroundTruth, PoseAtInterpolatesOnlyNearSamples)
{
    core::Trajectory traj;
    traj.poses.push_back({10.0, mrpt::poses::CPose3D(0, 0, 0, 0, 0, 0)});
    traj.poses.push_back({10.05, mrpt::poses::CPose3D(1, 0, 0, 0, 0, 0)});
    traj.poses.push_back({20.0, mrpt::poses::CPose3D(2, 0, 0, 0, 0, 0)});
    const double dt = 0.005;
    ASSERT_TRUE(poseAt(traj, 10.004, dt));
    EXPECT_NEAR(poseAt(traj, 10.004, dt)->x(), 0.08, 1e-9);  // interpolated, not the nearest sample
    EXPECT_FALSE(poseAt(traj, 10.025, dt));                  // 25 ms from both samples
    EXPECT_FALSE(poseAt(traj, 9.99, dt));                    // before the start: no extrapolation
    ASSERT_TRUE(poseAt(traj, 9.996, dt));
    EXPECT_NEAR(poseAt(traj, 9.996, dt)->x(), 0.0, 1e-12);  // the first sample, within max_dt_s
    EXPECT_FALSE(poseAt(traj, 15.0, dt));                   // inside a gap of the trajectory
    EXPECT_NEAR(poseAt(traj, 20.004, dt)->x(), 2.0, 1e-12);
    EXPECT_FALSE(poseAt(core::Trajectory{}, 10.0, dt));
}

TEST(GroundTruth, ReadsTumAndDropsRepeatedTimestamps)
{
    TempDir dir;
    std::ofstream(dir / "gt.txt") << "# T_world_cam0\n"
                                     "5.0 1 2 3 0 0 0 1\n5.0 1 2 3 0 0 0 1\n5.0 1 2 3 0 0 0 1\n"
                                     "5.05 1.1 2 3 0 0 0 1\n5.1 1.2 2 3 0 0 0 1\n";
    const auto gt = readGroundTruthCam0(dir / "gt.txt", mrpt::poses::CPose3D(9, 9, 9, 0, 0, 0));
    EXPECT_EQ(gt.kind, GroundTruthFile::Kind::TumCam0);
    EXPECT_EQ(gt.duplicate_rows_dropped, 2u);
    ASSERT_EQ(gt.T_world_cam0.poses.size(), 3u);
    EXPECT_NEAR(gt.T_world_cam0.poses[1].pose.x(), 1.1, 1e-12);  // taken as is: T_body_cam0 not applied

    const auto restricted = restrictToSpan(gt.T_world_cam0, 5.04, 5.06, 0.02);
    ASSERT_EQ(restricted.poses.size(), 1u);
    EXPECT_DOUBLE_EQ(restricted.poses[0].t, 5.05);

    std::ofstream(dir / "bad.txt") << "5.0 1 2 3 0 0 0\n";
    test::expectInputErrorMentioning([&] { readGroundTruthCam0(dir / "bad.txt", {}); }, "bad.txt:1");
    std::ofstream(dir / "bad.csv") << "1403715273262142976,1,2,3,1,0,0,0,x,0,0\n1403715273262142977,1,2\n";
    test::expectInputErrorMentioning([&] { readGroundTruthCam0(dir / "bad.csv", {}); }, "bad.csv:2");
    std::ofstream(dir / "empty.txt") << "# nothing\n";
    test::expectInputErrorMentioning([&] { readGroundTruthCam0(dir / "empty.txt", {}); }, "empty.txt");
}
