#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <algorithm>
#include <quasiloc/core/error.h>
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/eval/report.h>
#include <quasiloc/eval/sequence_eval.h>
#include <sstream>

#include "json_test_parser.h"

using mrpt::poses::CPose3D;
using namespace quasiloc::eval;
using quasiloc::eval::testing::JsonParser;
using quasiloc::eval::testing::JsonValue;

namespace
{
class ReportTest : public ::testing::Test
{
   protected:
    void SetUp() override
    {
        dir_ = std::filesystem::temp_directory_path() / ("quasiloc_eval_report_" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir_);
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }

    /** Tracking: a helix at 10 Hz; the estimate is shifted 5 cm along x, misses two poses and has one
     *  extra pose 1 s after the end (unmatched). */
    NamedSequence writeTracking()
    {
        quasiloc::core::Trajectory gt, est;
        for (int i = 0; i < 40; ++i)
        {
            const double a = 0.15 * i;
            const CPose3D g(std::cos(a), std::sin(a), 0.02 * i, a, 0, 0);
            gt.poses.push_back({100.0 + 0.1 * i, g});
            if (i != 7 && i != 8) est.poses.push_back({100.0 + 0.1 * i + 0.003, CPose3D(0.05, 0, 0, 0, 0, 0) + g});
        }
        est.poses.push_back({105.0, CPose3D()});
        quasiloc::core::writeTum(path("trk_gt.tum"), gt);
        quasiloc::core::writeTum(path("trk_est.tum"), est);
        NamedSequence s{"trk", "Eval.trk", {}};
        s.options.estimate = path("trk_est.tum");
        s.options.groundtruth = path("trk_gt.tum");
        return s;
    }

    /** Localization: 5 queries, 3 localized with errors 0.05, 0.2 and 0.8 m. */
    NamedSequence writeLocalization()
    {
        quasiloc::core::Trajectory gt, est;
        std::ofstream q(path("loc_queries.txt"));
        const double err[5] = {0.05, -1, 0.2, -1, 0.8};
        for (int i = 0; i < 5; ++i)
        {
            const CPose3D g(i, 0, 0, 0, 0, 0);
            gt.poses.push_back({10.0 + i, g});
            q << 10.0 + i << "\n";
            if (err[i] >= 0) est.poses.push_back({10.0 + i, CPose3D(i, err[i], 0, 0, 0, 0)});
        }
        quasiloc::core::writeTum(path("loc_gt.tum"), gt);
        quasiloc::core::writeTum(path("loc_est.tum"), est);
        NamedSequence s{"loc \"x\"", "Eval.loc", {}};  // a name that needs JSON escaping
        s.options.kind = SequenceKind::Localization;
        s.options.estimate = path("loc_est.tum");
        s.options.groundtruth = path("loc_gt.tum");
        s.options.queries = path("loc_queries.txt");
        return s;
    }

    std::filesystem::path dir_;
};
}  // namespace

TEST_F(ReportTest, JsonParsesAndHoldsTheFigures)
{
    EvalOptions opts;
    opts.align = Alignment::SE3;
    const std::vector<SequenceReport> reports = {evaluateSequence(writeTracking(), opts),
                                                 evaluateSequence(writeLocalization(), opts)};
    const JsonValue v = JsonParser::parse(jsonReport(reports, opts));
    EXPECT_EQ(v["settings"]["align"].string, "se3");
    ASSERT_EQ(v["sequences"].array.size(), 2u);
    const JsonValue& trk = v["sequences"][0];
    EXPECT_EQ(trk["association"]["matched"].number, 38);
    EXPECT_EQ(trk["association"]["unmatched_estimate"].number, 1);
    EXPECT_EQ(trk["association"]["unmatched_groundtruth"].number, 2);
    EXPECT_NEAR(trk["association"]["max_abs_dt_s"].number, 0.003, 1e-6);
    EXPECT_NEAR(trk["ate_rmse_m"].number, 0.05, 1e-6);
    EXPECT_NEAR(trk["ate"]["translation_m"]["max"].number, 0.05, 1e-6);
    EXPECT_LT(trk["ate_se3_rmse_m"].number, 1e-6);
    EXPECT_LT(trk["ate_sim3_rmse_m"].number, 1e-6);
    EXPECT_NEAR(trk["sim3_scale"].number, 1.0, 1e-6);
    EXPECT_NEAR(trk["ate_se3"]["transform"]["translation_m"][0].number, -0.05, 1e-6);
    EXPECT_EQ(trk["ate_se3"]["transform"]["matrix"].array.size(), 4u);
    EXPECT_FALSE(trk["ate_se3"]["transform"]["degenerate"].boolean);
    EXPECT_EQ(trk["ate_sim3"]["alignment"].string, "sim3");
    EXPECT_GT(trk["rpe_per_s"]["translation_m"]["count"].number, 20);
    EXPECT_EQ(trk["rpe_per_s"]["delta_unit"].string, "s");
    EXPECT_EQ(trk["rpe_per_m"]["delta_unit"].string, "m");
    EXPECT_LT(trk["rpe_per_m_trans_rmse_m"].number, 1e-6);  // a constant offset has no relative error
    const JsonValue& loc = v["sequences"][1];
    EXPECT_EQ(loc["name"].string, "loc \"x\"");
    EXPECT_EQ(loc["queries"]["total"].number, 5);
    EXPECT_EQ(loc["queries"]["not_localized"].number, 2);
    EXPECT_NEAR(loc["mate_m"].number, (0.05 + 0.2 + 0.8) / 3, 1e-6);
    ASSERT_EQ(loc["recall"].array.size(), 3u);
    EXPECT_DOUBLE_EQ(loc["recall"][0]["recall"].number, 0.2);                  // <= 0.1 m: 1 of 5
    EXPECT_DOUBLE_EQ(loc["recall"][1]["recall"].number, 0.4);                  // <= 0.3 m: 2 of 5
    EXPECT_DOUBLE_EQ(loc["recall"][2]["recall"].number, 0.6);                  // <= 1.0 m: 3 of 5
    EXPECT_EQ(loc["recall"][0]["threshold_deg"].type, JsonValue::Type::Null);  // no rotation bound
}

TEST_F(ReportTest, MarkdownShowsUnalignedFirstInCentimetres)
{
    EvalOptions opts;
    opts.align = Alignment::Sim3;
    const std::vector<SequenceReport> reports = {evaluateSequence(writeTracking(), opts),
                                                 evaluateSequence(writeLocalization(), opts)};
    const std::string md = markdownReport(reports, opts);
    const auto unaligned = md.find("ATE, map frame (no alignment)");
    const auto aligned = md.find("ATE after Sim(3) alignment");
    ASSERT_NE(unaligned, std::string::npos);
    ASSERT_NE(aligned, std::string::npos);
    EXPECT_LT(unaligned, aligned);
    EXPECT_NE(md.find("| trk | 39 | 40 | 38 | 1 | 5.00 | 5.00 | 5.00 | 0.00 | 5.00 | 5.00 |"), std::string::npos) << md;
    EXPECT_LT(md.find("ATE after SE(3) alignment"), aligned);
    EXPECT_NE(md.find("RPE per 1 m of path (evo_rpe --delta 1 --delta_unit m"), std::string::npos) << md;
    EXPECT_NE(md.find("RPE per 1 s (TUM evaluate_rpe.py"), std::string::npos) << md;
    EXPECT_NE(md.find("| 20.0 % | 40.0 % | 60.0 % | 35.00 |"), std::string::npos) << md;
    EXPECT_NE(md.find("scale 1.000000"), std::string::npos) << md;
    // The per-pose table: header + one line per associated pose.
    const std::string csv = errorsCsv(reports[0]);
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 39);
    EXPECT_EQ(
        csv.substr(0, csv.find('\n')),
        "t_est,t_gt,dt_s,trans_err_m,rot_err_deg,trans_err_se3_m,rot_err_se3_deg,trans_err_sim3_m,rot_err_sim3_deg");
    const std::string loc_csv = errorsCsv(reports[1]);
    EXPECT_NE(loc_csv.find("11.000000000,not_localized,,\n"), std::string::npos) << loc_csv;
}

TEST_F(ReportTest, TrackingWithoutAnyAssociationIsAnError)
{
    NamedSequence s = writeTracking();
    EvalOptions opts;
    opts.max_dt_s = 0.001;  // the estimate is 3 ms late everywhere
    EXPECT_THROW(evaluateSequence(s, opts), quasiloc::core::InputError);
}

TEST_F(ReportTest, RealEurocGroundTruthAgainstARotatedCopy)
{
    // V1_01 ground truth (T_world_cam0) against a copy expressed in a world rotated by 2 deg about z:
    // the unaligned rotation error is 2 deg for every pose, the SE(3)-aligned ATE vanishes.
    const std::string gt_path = std::string(QUASILOC_SHARED_DIR) + "/data/euroc/groundtruth/cam0/V1_01_easy.txt";
    quasiloc::core::Trajectory est = quasiloc::core::readTum(gt_path);
    const CPose3D T_off(0.1, -0.05, 0.02, 2.0 * M_PI / 180.0, 0, 0);
    for (auto& p : est.poses) p.pose = T_off + p.pose;
    quasiloc::core::writeTum(path("v101_est.tum"), est);
    NamedSequence s{"v101", "Eval.v101", {}};
    s.options.estimate = path("v101_est.tum");
    s.options.groundtruth = gt_path;
    EvalOptions opts;
    opts.align = Alignment::SE3;
    const SequenceReport r = evaluateSequence(s, opts);
    EXPECT_EQ(r.duplicates_gt, r.duplicates_est);
    EXPECT_GT(r.duplicates_gt, 0u);  // EuRoC repeats rows before ground truth starts
    EXPECT_EQ(r.tracking.association.matches.size(), r.num_gt);
    EXPECT_NEAR(r.tracking.ate.rot_deg.min, 2.0, 1e-5);
    EXPECT_NEAR(r.tracking.ate.rot_deg.max, 2.0, 1e-5);
    EXPECT_GT(r.tracking.ate.trans_m.mean, 0.05);
    EXPECT_LT(r.tracking.ate_se3->trans_m.rmse, 1e-6);  // TUM files hold translations to 0.1 um
    ASSERT_EQ(r.tracking.rpe.size(), 2u);               // per metre and per second
    EXPECT_GT(r.tracking.rpe[0].trans_m.count, 20u);
    EXPECT_LT(r.tracking.rpe[0].trans_m.max, 1e-6);
    EXPECT_LT(r.tracking.rpe[1].trans_m.max, 1e-6);
}
