#include <gtest/gtest.h>

#include <quasiloc/core/error.h>
#include <quasiloc/eval/association.h>
#include <random>

using quasiloc::eval::associateByTime;

TEST(Association, JitteredTimestampsWithinMaxDt)
{
    // Ground truth at 20 Hz; estimates at the same instants with +-8 ms jitter, plus two far off.
    std::vector<double> gt, est;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-0.008, 0.008);
    for (int i = 0; i < 100; ++i) gt.push_back(1000.0 + 0.05 * i);
    for (int i = 0; i < 100; i += 2) est.push_back(gt[i] + jitter(rng));
    est.push_back(999.0);           // before the ground truth
    est.push_back(1002.0 + 0.025);  // half-way between two gt samples: |dt| = 25 ms > 20 ms
    const auto a = associateByTime(est, gt, 0.02);
    ASSERT_EQ(a.matches.size(), 50u);
    ASSERT_EQ(a.unmatched_est.size(), 2u);
    EXPECT_EQ(a.unmatched_est[0], 50u);
    EXPECT_EQ(a.unmatched_est[1], 51u);
    EXPECT_EQ(a.unmatched_gt, 50u);
    for (size_t k = 0; k < a.matches.size(); ++k)
    {
        EXPECT_EQ(a.matches[k].est_index, k);
        EXPECT_EQ(a.matches[k].gt_index, 2 * k);  // the nearest gt sample, not a neighbour
        EXPECT_LE(std::abs(a.matches[k].dt_s), 0.008);
    }
    EXPECT_LE(a.max_abs_dt_s, 0.008);
}

TEST(Association, OneToOneGreedyBySmallestDt)
{
    // Two estimates compete for gt 10.0: est 10.004 is nearer and wins; est 9.99 falls back to gt 9.98
    // (|dt| 10 ms) rather than staying unmatched. A third estimate has only gt 10.0 in range: unmatched.
    const std::vector<double> gt = {9.98, 10.0};
    const std::vector<double> est = {9.99, 10.004, 10.005};
    const auto a = associateByTime(est, gt, 0.015);
    ASSERT_EQ(a.matches.size(), 2u);
    EXPECT_EQ(a.matches[0].est_index, 0u);
    EXPECT_EQ(a.matches[0].gt_index, 0u);
    EXPECT_EQ(a.matches[1].est_index, 1u);
    EXPECT_EQ(a.matches[1].gt_index, 1u);
    ASSERT_EQ(a.unmatched_est.size(), 1u);
    EXPECT_EQ(a.unmatched_est[0], 2u);
    EXPECT_EQ(a.unmatched_gt, 0u);
    // Each gt index used once.
    EXPECT_NE(a.matches[0].gt_index, a.matches[1].gt_index);
}

TEST(Association, UnsortedInputsBoundaryAndBadMaxDt)
{
    const std::vector<double> gt = {3.0, 1.0, 2.0};
    const std::vector<double> est = {2.25, 1.0, 3.5};
    const auto a = associateByTime(est, gt, 0.25);  // 2.25 - 2.0 = 0.25 exactly: inclusive bound
    ASSERT_EQ(a.matches.size(), 2u);
    EXPECT_EQ(a.matches[0].est_index, 0u);
    EXPECT_EQ(a.matches[0].gt_index, 2u);
    EXPECT_EQ(a.matches[1].gt_index, 1u);
    EXPECT_EQ(a.unmatched_est, std::vector<size_t>{2});
    EXPECT_THROW(associateByTime(est, gt, -1.0), quasiloc::core::InputError);
    EXPECT_TRUE(associateByTime({}, gt, 0.1).matches.empty());
}

TEST(Association, DropDuplicateTimestamps)
{
    quasiloc::core::Trajectory traj;
    for (double t : {1.0, 1.0, 1.0, 2.0, 3.0, 3.0}) traj.poses.push_back({t, mrpt::poses::CPose3D(t, 0, 0, 0, 0, 0)});
    traj.poses[1].pose = mrpt::poses::CPose3D(99, 0, 0, 0, 0, 0);
    EXPECT_EQ(quasiloc::eval::dropDuplicateTimestamps(traj), 3u);
    ASSERT_EQ(traj.poses.size(), 3u);
    EXPECT_EQ(traj.poses[0].pose.x(), 1.0);  // the first of the repeated poses is kept
    EXPECT_EQ(traj.poses[2].t, 3.0);
}
