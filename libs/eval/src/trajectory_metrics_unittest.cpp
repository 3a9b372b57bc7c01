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
    for (auto& p : pairs) p.est = CPose3D(0.5 * p.gt.x(), 0.5 * p.gt.y(), 0.5 * p.gt.z(), p.gt.yaw(), p.gt.pitch(), p.gt.roll());
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
    const RpeResult one = computeRpe(pairs, RpeDelta{0, 1});
    EXPECT_EQ(one.trans_m.count, 19u);
    EXPECT_NEAR(one.trans_m.rmse, 0.01, 1e-12);
    EXPECT_NEAR(one.trans_m.max, 0.01, 1e-12);
    EXPECT_NEAR(one.rot_deg.mean, 0.5, 1e-9);
    const RpeResult secs = computeRpe(pairs, RpeDelta{1.0, 0});
    EXPECT_EQ(secs.trans_m.count, 19u);
    EXPECT_NEAR(secs.trans_m.mean, 0.01, 1e-12);
    // Two steps: est relative motion (1.01 (1 + cos 0.5deg), 1.01 sin 0.5deg), yaw 1 deg; gt (2, 0).
    const RpeResult two = computeRpe(pairs, RpeDelta{0, 2});
    const double ex = 1.01 * (1 + std::cos(0.5 * kDeg)) - 2, ey = 1.01 * std::sin(0.5 * kDeg);
    EXPECT_EQ(two.trans_m.count, 18u);
    EXPECT_NEAR(two.trans_m.median, std::hypot(ex, ey), 1e-12);
    EXPECT_NEAR(two.rot_deg.median, 1.0, 1e-9);
    EXPECT_THROW(computeRpe(pairs, RpeDelta{1.0, 1}), quasiloc::core::InputError);
}

TEST(TrajectoryMetrics, RpeInSecondsSkipsGaps)
{
    // Poses at 0,1,2 then a gap to 5,6: a 1 s delta has partners 0-1, 1-2, 5-6 only.
    std::vector<PosePair> pairs;
    for (double t : {0.0, 1.0, 2.0, 5.0, 6.0})
        pairs.push_back({t, t, CPose3D(t + 0.02 * t, 0, 0, 0, 0, 0), CPose3D(t, 0, 0, 0, 0, 0)});
    const RpeResult r = computeRpe(pairs, RpeDelta{1.0, 0});
    EXPECT_EQ(r.trans_m.count, 3u);
    EXPECT_NEAR(r.trans_m.max, 0.02, 1e-12);
}

TEST(TrajectoryMetrics, AlignmentNames)
{
    EXPECT_EQ(toString(Alignment::SE3), "se3");
    EXPECT_EQ(toString(Alignment::Sim3), "sim3");
    EXPECT_EQ(toString(Alignment::None), "none");
    EXPECT_EQ(alignmentNames().size(), 3u);
}
