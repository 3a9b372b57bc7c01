#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <quasiloc/core/error.h>
#include <quasiloc/eval/localization_metrics.h>

using mrpt::poses::CPose3D;
using namespace quasiloc::eval;

namespace
{
constexpr double kDeg = M_PI / 180.0;

quasiloc::core::Trajectory groundTruth()
{
    quasiloc::core::Trajectory gt;
    for (int i = 0; i < 10; ++i) gt.poses.push_back({double(i), CPose3D(i, 0.5 * i, 1, 0.1 * i, 0, 0)});
    return gt;
}

/** Localized at t = 0,1,2,3,5,7 with translation errors 0.05, 0.2, 0.5, 2.0, 0.08, 0.25 m; the 0.2 m one
 *  is also off by 5 deg in rotation. Queries 4, 6, 8, 9 are not localized. */
quasiloc::core::Trajectory estimate(const quasiloc::core::Trajectory& gt)
{
    const std::vector<std::pair<int, double>> localized = {{0, 0.05}, {1, 0.2},  {2, 0.5},
                                                           {3, 2.0},  {5, 0.08}, {7, 0.25}};
    quasiloc::core::Trajectory est;
    for (const auto& [i, err] : localized)
    {
        const CPose3D& g = gt.poses[size_t(i)].pose;
        CPose3D e(g.x(), g.y() + err, g.z(), g.yaw(), g.pitch(), g.roll());
        if (i == 1) e = CPose3D(g.x(), g.y() + err, g.z(), g.yaw() + 5 * kDeg, g.pitch(), g.roll());
        est.poses.push_back({double(i) + 1e-4, e});  // timestamps as written by a program: tiny rounding
    }
    return est;
}

std::vector<double> allQueries()
{
    std::vector<double> q;
    for (int i = 0; i < 10; ++i) q.push_back(i);
    return q;
}
}  // namespace

TEST(LocalizationMetrics, RecallAndMateCountNotLocalized)
{
    const auto gt = groundTruth();
    const std::vector<RecallThreshold> thr = {{0.1}, {0.3}, {1.0}};
    const auto r = evaluateLocalization(estimate(gt), gt, allQueries(), true, 0.02, thr, "est");
    EXPECT_EQ(r.num_queries, 10u);
    EXPECT_EQ(r.num_evaluated, 10u);
    EXPECT_EQ(r.num_localized, 6u);
    EXPECT_EQ(r.num_no_ground_truth, 0u);
    ASSERT_EQ(r.recall.size(), 3u);
    EXPECT_EQ(r.recall[0].count, 2u);
    EXPECT_DOUBLE_EQ(r.recall[0].recall, 0.2);
    EXPECT_DOUBLE_EQ(r.recall[1].recall, 0.4);
    EXPECT_DOUBLE_EQ(r.recall[2].recall, 0.5);
    EXPECT_NEAR(r.trans_m.mean, (0.05 + 0.2 + 0.5 + 2.0 + 0.08 + 0.25) / 6, 1e-12);      // mATE of all localized
    EXPECT_NEAR(r.recall[2].trans_m.mean, (0.05 + 0.2 + 0.5 + 0.08 + 0.25) / 5, 1e-12);  // within 1 m
    EXPECT_NEAR(r.rot_deg.max, 5.0, 1e-9);
    EXPECT_EQ(r.queries[4].status, QueryStatus::NotLocalized);
    EXPECT_EQ(r.queries[3].status, QueryStatus::Localized);
    EXPECT_NEAR(r.queries[3].trans_err_m, 2.0, 1e-12);
}

TEST(LocalizationMetrics, RotationThresholdsAndQueriesWithoutGroundTruth)
{
    const auto gt = groundTruth();
    std::vector<double> queries = allQueries();
    queries.push_back(50.0);  // queried, not localized, and no ground truth there
    const std::vector<RecallThreshold> thr = {{0.3, 2.0}, {0.3}};
    const auto r = evaluateLocalization(estimate(gt), gt, queries, true, 0.02, thr, "est");
    EXPECT_EQ(r.num_queries, 11u);
    EXPECT_EQ(r.num_no_ground_truth, 1u);
    EXPECT_EQ(r.num_evaluated, 10u);   // the denominator excludes the query without ground truth
    EXPECT_EQ(r.recall[0].count, 3u);  // the 0.2 m / 5 deg query fails the 2 deg bound
    EXPECT_EQ(r.recall[1].count, 4u);
    EXPECT_DOUBLE_EQ(r.recall[0].recall, 0.3);
    EXPECT_EQ(r.queries.back().status, QueryStatus::NoGroundTruth);
}

TEST(LocalizationMetrics, WithoutQueryListEveryEstimateIsAQuery)
{
    const auto gt = groundTruth();
    const auto r = evaluateLocalization(estimate(gt), gt, {}, false, 0.02, {{1.0}}, "est");
    EXPECT_EQ(r.num_queries, 6u);
    EXPECT_EQ(r.num_localized, 6u);
    EXPECT_DOUBLE_EQ(r.recall[0].recall, 5.0 / 6.0);
}

TEST(LocalizationMetrics, EstimateOutsideTheQueryListIsAnError)
{
    const auto gt = groundTruth();
    auto est = estimate(gt);
    est.poses.push_back({4.5, CPose3D()});
    try
    {
        evaluateLocalization(est, gt, allQueries(), true, 0.02, {{1.0}}, "est.tum");
        FAIL() << "expected InputError";
    }
    catch (const quasiloc::core::InputError& e)
    {
        EXPECT_EQ(e.input(), "est.tum");
        EXPECT_NE(std::string(e.what()).find("4.5"), std::string::npos) << e.what();
    }
}

TEST(LocalizationMetrics, ReadQueryTimestamps)
{
    const auto dir = std::filesystem::temp_directory_path() / ("quasiloc_eval_queries_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string good = (dir / "good.txt").string(), bad = (dir / "bad.txt").string(),
                      dup = (dir / "dup.txt").string();
    std::ofstream(good) << "# t\n3.5\n\n1.25, not_localized\n  2.0 extra columns\n";
    std::ofstream(bad) << "1.0\nabc\n";
    std::ofstream(dup) << "1.0\n1.0\n";
    EXPECT_EQ(readQueryTimestamps(good), (std::vector<double>{1.25, 2.0, 3.5}));
    EXPECT_THROW(readQueryTimestamps(bad), quasiloc::core::InputError);
    EXPECT_THROW(readQueryTimestamps(dup), quasiloc::core::InputError);
    EXPECT_THROW(readQueryTimestamps((dir / "missing.txt").string()), quasiloc::core::InputError);
    try
    {
        readQueryTimestamps(bad);
    }
    catch (const quasiloc::core::InputError& e)
    {
        EXPECT_EQ(e.input(), bad + ":2");
    }
    std::filesystem::remove_all(dir);
}
