#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <unistd.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <quasiloc/core/error.h>
#include <quasiloc/eval/eval_config.h>

using namespace quasiloc::eval;

namespace
{
class EvalConfigTest : public ::testing::Test
{
   protected:
    void SetUp() override
    {
        dir_ = std::filesystem::temp_directory_path() / ("quasiloc_eval_config_" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir_);
        est_ = (dir_ / "est.tum").string();
        gt_ = (dir_ / "gt.tum").string();
        std::ofstream(est_) << "0 0 0 0 0 0 0 1\n";
        std::ofstream(gt_) << "0 0 0 0 0 0 0 1\n";
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }

    std::string base() const
    {
        return "[Eval]\noutput_dir = " + (dir_ / "out").string() +
               "\nsequence_names = [a b]\nalign = SE3\n"
               "recall_thresholds_m = [0.25, 0.5]\nrecall_thresholds_deg = [2 5]\n\n"
               "[Eval.a]\nkind = tracking\nestimate = " +
               est_ + "\ngroundtruth = " + gt_ +
               "\n\n"
               "[Eval.b]\nkind = localization\nestimate = " +
               est_ + "\ngroundtruth = " + gt_ + "\nqueries = " + est_ + "\n\n[OtherProgram]\nwhatever = 1\n";
    }
    using Overrides = std::vector<std::array<std::string, 3>>;  // section, key, value (as --set does)
    EvalConfig load(const Overrides& overrides = {}, const std::string& text = "") const
    {
        mrpt::config::CConfigFileMemory cfg(text.empty() ? base() : text);
        for (const auto& [section, key, value] : overrides) cfg.write(section, key, value);
        return loadEvalConfig(cfg, "test.ini");
    }
    std::string loadError(const Overrides& overrides, const std::string& text = "") const
    {
        try
        {
            load(overrides, text);
        }
        catch (const quasiloc::core::InputError& e)
        {
            return e.what();
        }
        return "";
    }

    std::filesystem::path dir_;
    std::string est_, gt_;
};
}  // namespace

TEST_F(EvalConfigTest, LoadsSequencesAndLists)
{
    const EvalConfig c = load();
    EXPECT_EQ(c.eval.sequence_names, (std::vector<std::string>{"a", "b"}));
    EXPECT_EQ(c.eval.align, Alignment::SE3);  // names match without regard to case
    EXPECT_DOUBLE_EQ(c.eval.max_dt_s, 0.02);  // default
    const auto thr = c.eval.recallThresholds();
    ASSERT_EQ(thr.size(), 2u);
    EXPECT_DOUBLE_EQ(thr[1].trans_m, 0.5);
    EXPECT_DOUBLE_EQ(thr[1].rot_deg, 5.0);
    ASSERT_EQ(c.sequences.size(), 2u);
    EXPECT_EQ(c.sequences[1].section, "Eval.b");
    EXPECT_EQ(c.sequences[1].options.kind, SequenceKind::Localization);
    EXPECT_EQ(c.sequences[0].options.estimate, est_);
}

TEST_F(EvalConfigTest, DottedOverrideReachesTheSequenceSection)
{
    // "--set Eval.a.kind=localization" arrives as key "a.kind" of [Eval].
    const EvalConfig c = load({{"Eval", "a.kind", "localization"}});
    EXPECT_EQ(c.sequences[0].options.kind, SequenceKind::Localization);
    EXPECT_NE(loadError({{"Eval", "zz.kind", "tracking"}}).find("not listed"), std::string::npos);
}

TEST_F(EvalConfigTest, RejectsBadConfigurations)
{
    EXPECT_NE(loadError({{"Eval", "max_dt", "0.1"}}).find("unknown key"), std::string::npos);
    EXPECT_NE(loadError({{"Eval.a", "estimat", "x"}}).find("unknown key"), std::string::npos);
    EXPECT_NE(loadError({{"Eval.c", "kind", "tracking"}}).find("not listed"), std::string::npos);
    EXPECT_NE(loadError({{"Eval.a", "estimate", "/nonexistent/est.tum"}}).find("file not found"), std::string::npos);
    EXPECT_NE(loadError({{"Eval.a", "queries", est_}}).find("only a localization"), std::string::npos);
    EXPECT_NE(loadError({{"Eval.a", "kind", "slam"}}).find("'slam' is not one of tracking, localization"),
              std::string::npos);
    EXPECT_NE(loadError({{"Eval", "max_dt_s", "fast"}}).find("not a finite number"), std::string::npos);
    EXPECT_NE(loadError({{"Eval", "max_dt_s", "-1"}}).find("max_dt_s"), std::string::npos);
    EXPECT_NE(loadError({{"Eval", "align", "umeyama"}}).find("'umeyama' is not one of none, se3, sim3"),
              std::string::npos);
    EXPECT_NE(loadError({{"Eval", "recall_thresholds_m", "[0.1 0]"}}).find("recall_thresholds_m"), std::string::npos);
    EXPECT_NE(loadError({{"Eval", "rpe_delta_m", "0"}, {"Eval", "rpe_delta_s", "0"}}).find("at least one"),
              std::string::npos);
    EXPECT_NE(loadError({{"Eval", "association", "linear"}}).find("'linear' is not one of nearest, interpolated"),
              std::string::npos);
    EXPECT_NE(loadError({{"Eval", "recall_thresholds_deg", "[1]"}}).find("one value per"), std::string::npos);
    EXPECT_NE(loadError({{"Eval", "sequence_names", "[a b c]"}}).find("section is missing"), std::string::npos);
    EXPECT_NE(loadError({{"Eval", "sequence_names", "[a a]"}}).find("listed twice"), std::string::npos);
    EXPECT_NE(loadError({}, "[Other]\nx = 1\n").find("[Eval] is missing"), std::string::npos);
    // The deltas that are > 0, in the order metres, seconds, frames.
    const auto deltas = load({{"Eval", "rpe_delta_frames", "3"}, {"Eval", "rpe_delta_s", "0"}}).eval.rpeDeltas();
    ASSERT_EQ(deltas.size(), 2u);
    EXPECT_EQ(deltas[0].unit, RpeUnit::Metres);
    EXPECT_EQ(deltas[1].unit, RpeUnit::Frames);
    EXPECT_EQ(deltas[1].value, 3.0);
}

TEST_F(EvalConfigTest, SequenceNamesMayBeSeparatedByCommas)
{
    EXPECT_EQ(load({{"Eval", "sequence_names", " a,b "}}).eval.sequence_names, (std::vector<std::string>{"a", "b"}));
}
