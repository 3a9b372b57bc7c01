#include <gtest/gtest.h>

#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/eval/trajectory_metrics.h>

using mrpt::poses::CPose3D;
using namespace quasiloc::eval;

namespace
{
constexpr double kDeg = M_PI / 180.0;

/** A helix with changing orientation: positions not collinear, so alignments are well defined. */
std::vector<PosePair> helixPairs(int n)
{
    std::vector<PosePair> pairs;
    for (int i = 0; i < n; ++i)
    {
        const double a = 0.1 * i;
        const CPose3D gt(2 * std::cos(a), 2 * std::sin(a), 0.05 * i, a, 0.2 * std::sin(a), 0.1);
        pairs.push_back({0.05 * i, 0.05 * i, gt, gt});
    }
    return pairs;
}
}  // namespace

TEST(TrajectoryMetrics, AteOfThreePosesByHand)
{
    // Errors 0.1, 0.2, 0.6 m and rotation errors 0, 10, 20 deg.
    const CPose3D gt(1, 2, 3, 0.3, 0.1, -0.2);
    const Eigen::Isometry3d G = quasiloc::core::toIsometry(gt);
    const auto perturbed = [&](const Eigen::Vector3d& dt, const Eigen::Matrix3d& dR) {
        Eigen::Isometry3d E = G;
        E.translation() += dt;
        E.linear() = G.linear() * dR;
        return quasiloc::core::fromIsometry(E);
    };
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d Rz10 = Eigen::AngleAxisd(10 * kDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::Matrix3d Ry20 = Eigen::AngleAxisd(20 * kDeg, Eigen::Vector3d::UnitY()).toRotationMatrix();
    std::vector<PosePair> pairs;
    pairs.push_back({0, 0, perturbed({0.1, 0, 0}, I), gt});
    pairs.push_back({1, 1, perturbed({0, 0.2, 0}, Rz10), gt});
    pairs.push_back({2, 2, perturbed({0, 0, 0.6}, Ry20), gt});
    const AteResult r = computeAte(pairs, Alignment::None);
    ASSERT_EQ(r.trans_errors_m.size(), 3u);
    EXPECT_NEAR(r.trans_errors_m[0], 0.1, 1e-12);
    EXPECT_NEAR(r.trans_errors_m[1], 0.2, 1e-12);
    EXPECT_NEAR(r.trans_errors_m[2], 0.6, 1e-12);
    EXPECT_NEAR(r.trans_m.rmse, std::sqrt((0.01 + 0.04 + 0.36) / 3), 1e-12);
    EXPECT_NEAR(r.trans_m.mean, 0.3, 1e-12);
    EXPECT_NEAR(r.trans_m.median, 0.2, 1e-12);
    EXPECT_NEAR(r.trans_m.max, 0.6, 1e-12);
    EXPECT_NEAR(r.rot_errors_deg[0], 0.0, 1e-9);
    EXPECT_NEAR(r.rot_errors_deg[1], 10.0, 1e-9);
    EXPECT_NEAR(r.rot_errors_deg[2], 20.0, 1e-9);
    EXPECT_NEAR(r.rot_deg.mean, 10.0, 1e-9);
}

TEST(TrajectoryMetrics, TranslationOffsetUnalignedEqualsOffsetAlignedZero)
{
    auto pairs = helixPairs(80);
    const Eigen::Vector3d d(0.03, -0.04, 0.12);  // |d| = 0.13 m
    for (auto& p : pairs) p.est = CPose3D(d.x(), d.y(), d.z(), 0, 0, 0) + p.gt;
    const AteResult none = computeAte(pairs, Alignment::None);
    EXPECT_NEAR(none.trans_m.rmse, 0.13, 1e-12);
    EXPECT_NEAR(none.trans_m.min, 0.13, 1e-12);
    EXPECT_NEAR(none.trans_m.max, 0.13, 1e-12);
    EXPECT_NEAR(none.rot_deg.max, 0.0, 1e-9);
    const AteResult se3 = computeAte(pairs, Alignment::SE3);
    EXPECT_LT(se3.trans_m.max, 1e-9);
    EXPECT_LT((se3.transform.t + d).norm(), 1e-9);  // the alignment undoes the offset
}

TEST(TrajectoryMetrics, RigidOffsetWithRotationKnownRotationError)
{
    // est = T_off (+) gt: the whole estimate lives in a world rotated by 7 deg and shifted.
    auto pairs = helixPairs(60);
    const CPose3D T_off(0.5, -0.2, 0.1, 7 * kDeg, 0, 0);
    for (auto& p : pairs) p.est = T_off + p.gt;
    const AteResult none = computeAte(pairs, Alignment::None);
    EXPECT_NEAR(none.rot_deg.min, 7.0, 1e-9);  // every pose is off by the world rotation
    EXPECT_NEAR(none.rot_deg.max, 7.0, 1e-9);
    EXPECT_GT(none.trans_m.min, 0.1);
    for (Alignment a : {Alignment::SE3, Alignment::Sim3})
    {
        const AteResult al = computeAte(pairs, a);
        EXPECT_LT(al.trans_m.max, 1e-9) << toString(a);
        EXPECT_LT(al.rot_deg.max, 1e-6) << toString(a);
        EXPECT_NEAR(al.transform.scale, 1.0, 1e-9);
        const CPose3D inv = -T_off;
        EXPECT_LT((al.transform.R - inv.getRotationMatrix().asEigen()).norm(), 1e-9);
    }
}

TEST(TrajectoryMetrics, Sim3RemovesScale)
{
    auto pairs = helixPairs(50);
    for (auto& p : pairs)
        p.est = CPose3D(0.5 * p.gt.x(), 0.5 * p.gt.y(), 0.5 * p.gt.z(), p.gt.yaw(), p.gt.pitch(), p.gt.roll());
    const AteResult sim3 = computeAte(pairs, Alignment::Sim3);
    EXPECT_NEAR(sim3.transform.scale, 2.0, 1e-9);
    EXPECT_LT(sim3.trans_m.max, 1e-9);
    EXPECT_GT(computeAte(pairs, Alignment::SE3).trans_m.rmse, 0.1);
    EXPECT_THROW(computeAte({pairs[0], pairs[1]}, Alignment::SE3), quasiloc::core::InputError);
}

TEST(TrajectoryMetrics, RpeConstantDriftPerStep)
{
    // Ground truth steps 1 m along x each second; the estimate steps 1.01 m and turns 0.5 deg per step.
    std::vector<PosePair> pairs;
    CPose3D gt, est;
    const CPose3D step_gt(1, 0, 0, 0, 0, 0), step_est(1.01, 0, 0, 0.5 * kDeg, 0, 0);
    for (int i = 0; i < 20; ++i)
    {
        pairs.push_back({double(i), double(i), est, gt});
        gt = gt + step_gt;
        est = est + step_est;
    }
    const RpeResult one = computeRpe(pairs, RpeDelta{1, RpeUnit::Frames});
    EXPECT_EQ(one.trans_m.count, 19u);
    EXPECT_NEAR(one.trans_m.rmse, 0.01, 1e-12);
    EXPECT_NEAR(one.trans_m.max, 0.01, 1e-12);
    EXPECT_NEAR(one.rot_deg.mean, 0.5, 1e-9);
    const RpeResult secs = computeRpe(pairs, RpeDelta{1.0, RpeUnit::Seconds});
    EXPECT_EQ(secs.trans_m.count, 19u);
    EXPECT_NEAR(secs.trans_m.mean, 0.01, 1e-12);
    // Two steps: est relative motion (1.01 (1 + cos 0.5deg), 1.01 sin 0.5deg), yaw 1 deg; gt (2, 0).
    const RpeResult two = computeRpe(pairs, RpeDelta{2, RpeUnit::Frames});
    const double ex = 1.01 * (1 + std::cos(0.5 * kDeg)) - 2, ey = 1.01 * std::sin(0.5 * kDeg);
    EXPECT_EQ(two.trans_m.count, 18u);
    EXPECT_NEAR(two.trans_m.median, std::hypot(ex, ey), 1e-12);
    EXPECT_NEAR(two.rot_deg.median, 1.0, 1e-9);
    EXPECT_THROW(computeRpe(pairs, RpeDelta{1.5, RpeUnit::Frames}), quasiloc::core::InputError);
    EXPECT_THROW(computeRpe(pairs, RpeDelta{0, RpeUnit::Metres}), quasiloc::core::InputError);
}

TEST(TrajectoryMetrics, RpeInSecondsSkipsGaps)
{
    // Poses at 0,1,2 then a gap to 5,6: a 1 s delta has partners 0-1, 1-2, 5-6 only.
    std::vector<PosePair> pairs;
    for (double t : {0.0, 1.0, 2.0, 5.0, 6.0})
        pairs.push_back({t, t, CPose3D(t + 0.02 * t, 0, 0, 0, 0, 0), CPose3D(t, 0, 0, 0, 0, 0)});
    const RpeResult r = computeRpe(pairs, RpeDelta{1.0, RpeUnit::Seconds});
    EXPECT_EQ(r.trans_m.count, 3u);
    EXPECT_NEAR(r.trans_m.max, 0.02, 1e-12);
}

TEST(TrajectoryMetrics, EveryMetricOnASmallCaseByHand)
{
    // ATE. Ground truth: the corners of the unit square, g = (0,0,0) (1,0,0) (1,1,0) (0,1,0), identity rotations.
    // Estimate: twice as large, shifted by (1,0,0), z alternating +1 -1 +1 -1:
    //   e = (1,0,1) (3,0,-1) (3,2,1) (1,2,-1).
    // Unaligned: e - g = (1,0,1) (2,0,-1) (2,1,1) (1,1,-1), squared 2, 5, 6, 3: RMSE sqrt(16/4) = 2,
    //   mean (sqrt2 + sqrt5 + sqrt6 + sqrt3) / 4, max sqrt6, min sqrt2.
    // SE(3) (Umeyama): the cross-covariance of the centred sets is sum g_c e_c^T / 4 = diag(0.5, 0.5, 0) (the z
    //   signs cancel against the centred corners (-+.5, -+.5)), so R = I and t = mean(g) - mean(e) = (-1.5, -0.5, 0):
    //   e' - g = g_c + (0,0,+-1), |.|^2 = 0.5 + 1 for every pose: RMSE = min = max = sqrt(1.5).
    // Sim(3): scale = trace(D) / var(e) = (0.5 + 0.5) / ((4 * 0.5 + 4 * 1) / 4) = 1 / 3, R = I;
    //   e' - g = s e_c - g_c = (2s - 1) g_c + s (0,0,+-1), |.|^2 = (1/3)^2 0.5 + (1/3)^2 = 1/6: RMSE sqrt(1/6).
    const double z[4] = {1, -1, 1, -1};
    const double gx[4] = {0, 1, 1, 0}, gy[4] = {0, 0, 1, 1};
    std::vector<PosePair> square;
    for (int i = 0; i < 4; ++i)
        square.push_back({double(i), double(i), CPose3D(2 * gx[i] + 1, 2 * gy[i], z[i], 0, 0, 0),
                          CPose3D(gx[i], gy[i], 0, 0, 0, 0)});
    const AteResult raw = computeAte(square, Alignment::None);
    EXPECT_NEAR(raw.trans_m.rmse, 2.0, 1e-12);
    EXPECT_NEAR(raw.trans_m.mean, (std::sqrt(2.0) + std::sqrt(5.0) + std::sqrt(6.0) + std::sqrt(3.0)) / 4, 1e-12);
    EXPECT_NEAR(raw.trans_m.max, std::sqrt(6.0), 1e-12);
    EXPECT_NEAR(raw.trans_m.min, std::sqrt(2.0), 1e-12);
    const AteResult se3 = computeAte(square, Alignment::SE3);
    EXPECT_NEAR(se3.trans_m.rmse, std::sqrt(1.5), 1e-12);
    EXPECT_NEAR(se3.trans_m.min, std::sqrt(1.5), 1e-12);
    EXPECT_NEAR(se3.trans_m.max, std::sqrt(1.5), 1e-12);
    EXPECT_LT((se3.transform.t - Eigen::Vector3d(-1.5, -0.5, 0)).norm(), 1e-12);
    EXPECT_NEAR(se3.transform.scale, 1.0, 0);
    const AteResult sim3 = computeAte(square, Alignment::Sim3);
    EXPECT_NEAR(sim3.transform.scale, 1.0 / 3, 1e-12);
    EXPECT_LT((sim3.transform.R - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_NEAR(sim3.trans_m.rmse, std::sqrt(1.0 / 6), 1e-12);
    EXPECT_NEAR(sim3.trans_m.std, 0.0, 1e-12);

    // RPE. Ground truth along x every second: 0, 0.5, 1.0, 1.5, 2.0, 2.5 m (t = 0..5 s); the estimate
    // 0, 0.6, 1.1, 1.8, 2.2, 2.9 m. Identity rotations, so E_ij's translation is (e_j - e_i) - (g_j - g_i).
    // Per 0.45 m (evo, path of the estimate): steps 0.6, 0.5, 0.7, 0.4, 0.7; the path reaches 0.45 at pose 1
    //   (0.6), again at 2 (0.5), at 3 (0.7), then at 5 (0.4 + 0.7): pairs (1,2) (2,3) (3,5), errors
    //   |0.5 - 0.5| = 0, |0.7 - 0.5| = 0.2, |1.1 - 1.0| = 0.1: RMSE sqrt(0.05 / 3), mean 0.1, median 0.1, min 0,
    //   max 0.2, std sqrt((0.01 + 0.01 + 0) / 3). Pose 0 starts no pair (evo starts at the first pose that
    //   reaches the delta), and (3,4) is no pair (0.4 < 0.45).
    // Per 1 s (every pose, partner at t + 1 s): pairs (0,1) .. (4,5), errors 0.1, 0, 0.2, 0.1, 0.2: RMSE
    //   sqrt(0.1 / 5), mean 0.12, median 0.1, max 0.2, std sqrt(0.028 / 5).
    // Per 2 s: (0,2) (1,3) (2,4) (3,5), errors 0.1, 0.2, 0.1, 0.1: RMSE sqrt(0.07 / 4), median 0.1.
    const double g1[6] = {0, 0.5, 1.0, 1.5, 2.0, 2.5}, e1[6] = {0, 0.6, 1.1, 1.8, 2.2, 2.9};
    std::vector<PosePair> line;
    for (int i = 0; i < 6; ++i)
        line.push_back({double(i), double(i), CPose3D(e1[i], 0, 0, 0, 0, 0), CPose3D(g1[i], 0, 0, 0, 0, 0)});
    const auto by_path = rpeIndexPairs(line, {0.45, RpeUnit::Metres});
    EXPECT_EQ(by_path, (std::vector<std::pair<size_t, size_t>>{{1, 2}, {2, 3}, {3, 5}}));
    const RpeResult per_m = computeRpe(line, {0.45, RpeUnit::Metres});
    EXPECT_EQ(per_m.trans_m.count, 3u);
    EXPECT_NEAR(per_m.trans_m.rmse, std::sqrt(0.05 / 3), 1e-12);
    EXPECT_NEAR(per_m.trans_m.mean, 0.1, 1e-12);
    EXPECT_NEAR(per_m.trans_m.median, 0.1, 1e-12);
    EXPECT_NEAR(per_m.trans_m.min, 0.0, 1e-12);
    EXPECT_NEAR(per_m.trans_m.max, 0.2, 1e-12);
    EXPECT_NEAR(per_m.trans_m.std, std::sqrt(0.02 / 3), 1e-12);
    EXPECT_NEAR(per_m.rot_deg.max, 0.0, 1e-12);
    const RpeResult per_s = computeRpe(line, {1.0, RpeUnit::Seconds});
    EXPECT_EQ(per_s.trans_m.count, 5u);
    EXPECT_NEAR(per_s.trans_m.rmse, std::sqrt(0.1 / 5), 1e-12);
    EXPECT_NEAR(per_s.trans_m.mean, 0.12, 1e-12);
    EXPECT_NEAR(per_s.trans_m.median, 0.1, 1e-12);
    EXPECT_NEAR(per_s.trans_m.max, 0.2, 1e-12);
    EXPECT_NEAR(per_s.trans_m.std, std::sqrt(0.028 / 5), 1e-12);
    const RpeResult per_2s = computeRpe(line, {2.0, RpeUnit::Seconds});
    EXPECT_EQ(per_2s.trans_m.count, 4u);
    EXPECT_NEAR(per_2s.trans_m.rmse, std::sqrt(0.07 / 4), 1e-12);
    EXPECT_NEAR(per_2s.trans_m.median, 0.1, 1e-12);
}

TEST(TrajectoryMetrics, RpeIsMeasuredInTheFrameOfPoseI)
{
    // Both move 1 m along the world's x, but the estimate faces +y (yaw 90 deg) where the ground truth faces +x: in
    // its own frame the estimate moved 1 m to its right, (0,-1,0), the ground truth 1 m forward, (1,0,0), so
    // |t(E)| = |(0,-1,0) - (1,0,0)| = sqrt2 (E's rotation is identity). World-frame displacements would agree (0).
    const double h = M_PI / 2;
    const std::vector<PosePair> p = {{0, 0, CPose3D(0, 0, 0, h, 0, 0), CPose3D(0, 0, 0, 0, 0, 0)},
                                     {1, 1, CPose3D(1, 0, 0, h, 0, 0), CPose3D(1, 0, 0, 0, 0, 0)}};
    const RpeResult r = computeRpe(p, {1, RpeUnit::Frames});
    ASSERT_EQ(r.trans_m.count, 1u);
    EXPECT_NEAR(r.trans_m.max, std::sqrt(2.0), 1e-12);
    EXPECT_NEAR(r.rot_deg.max, 0.0, 1e-9);
}

TEST(TrajectoryMetrics, InterpolatedGroundTruthAtTheEstimateTimes)
{
    // Ground truth at 0, 0.1, 0.2 s moving 1 m/s along x and turning 10 deg/s; estimates at 0.04 s (x 0.04,
    // yaw 0.4 deg by interpolation), at 0.204 s (just past the end: the end sample) and at 0.3 s (too far: unpaired).
    quasiloc::core::Trajectory gt, est;
    for (int i = 0; i < 3; ++i) gt.poses.push_back({0.1 * i, CPose3D(0.1 * i, 0, 0, i * kDeg, 0, 0)});
    for (double t : {0.04, 0.204, 0.3}) est.poses.push_back({t, CPose3D(0.05, 0, 0, 0.5 * kDeg, 0, 0)});
    Association a;
    const auto pairs = makeInterpolatedPairs(est, gt, 0.05, a);
    ASSERT_EQ(pairs.size(), 2u);
    EXPECT_NEAR(pairs[0].gt.x(), 0.04, 1e-12);
    EXPECT_NEAR(pairs[0].gt.yaw(), 0.4 * kDeg, 1e-12);
    EXPECT_EQ(pairs[0].t_gt, 0.04);
    EXPECT_NEAR(pairs[1].gt.x(), 0.2, 1e-12);
    EXPECT_NEAR(pairs[1].gt.yaw(), 2 * kDeg, 1e-12);
    EXPECT_EQ(a.unmatched_est, (std::vector<size_t>{2}));
    ASSERT_EQ(a.matches.size(), 2u);
    EXPECT_EQ(a.matches[0].gt_index, 0u);  // the nearer sample
    EXPECT_EQ(a.unmatched_gt, 1u);         // the sample at 0.1 s is the nearer one of no estimate
    EXPECT_NEAR(a.max_abs_dt_s, 0.04, 1e-12);
}

TEST(TrajectoryMetrics, AlignmentNames)
{
    EXPECT_EQ(toString(Alignment::SE3), "se3");
    EXPECT_EQ(toString(Alignment::Sim3), "sim3");
    EXPECT_EQ(toString(Alignment::None), "none");
    EXPECT_EQ(alignmentNames().size(), 3u);
}
