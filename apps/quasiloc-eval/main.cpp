// quasiloc-eval: trajectory (ATE/RPE) and localization-query (recall/mATE) evaluation against ground truth.
//
//     quasiloc-eval <config.ini> [--set Eval.key=value]... [--set Eval.<name>.key=value]... [--print-timing]
//
// INI (full description in libs/eval/include/quasiloc/eval/eval_config.h; example: share/quasiloc/eval_example.ini):
//   [Eval]  output_dir, max_dt_s (0.02), align = none|se3|sim3 (none), rpe_delta_s (1.0) or rpe_delta_frames,
//           recall_thresholds_m ([0.1 0.3 1.0]), recall_thresholds_deg ([] = translation only),
//           sequence_names = [a b]
//   [Eval.a] kind = tracking|localization, estimate = <TUM>, groundtruth = <TUM>, queries = <timestamp list>
// Estimate and ground truth are TUM files (t tx ty tz qx qy qz qw) of T_map_cam. A localization estimate holds
// the localized queries only; `queries` lists every queried timestamp (one per line, '#' comments; the first
// column of a CSV/TUM also works), so that not-localized queries count as failures in the recall.
//
// Outputs in output_dir, written atomically (all or nothing): report.md (also printed to stdout),
// report.json, eval_effective.ini, <sequence>_errors.csv (per pose / per query errors).
// The unaligned map-frame ATE is always reported first; an alignment only adds a second table.
#include <mrpt/system/CTimeLogger.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/eval/eval_config.h>
#include <quasiloc/eval/report.h>
#include <quasiloc/eval/sequence_eval.h>

namespace
{
const char* kUsage =
    "usage: quasiloc-eval <config.ini> [--set Eval.key=value]... [--set Eval.<sequence>.key=value]... "
    "[--print-timing]\n"
    "Evaluates estimated trajectories / localization queries against ground truth (see "
    "share/quasiloc/eval_example.ini).";

void writeText(const std::string& path, const std::string& final_name, const std::string& text)
{
    std::ofstream f(path);
    quasiloc::core::require(f.good(), final_name, "cannot open for writing");
    f << text;
    f.close();
    quasiloc::core::require(!f.fail(), final_name, "write failed");
}

int run(const quasiloc::core::CommandLine& cmd)
{
    using namespace quasiloc;
    core::require(cmd.flags.empty(), "command line", "unexpected argument '" +
                                                         (cmd.flags.empty() ? std::string() : cmd.flags[0]) + "'");
    mrpt::system::CTimeLogger timer(cmd.print_timing, "quasiloc-eval");
    const auto cfg = core::loadConfig(cmd);
    const eval::EvalConfig config = eval::loadEvalConfig(cfg, cmd.config_path);

    std::vector<eval::SequenceReport> reports;
    for (const auto& seq : config.sequences)
    {
        mrpt::system::CTimeLoggerEntry t(timer, "evaluate");
        reports.push_back(eval::evaluateSequence(seq, config.eval));
    }

    timer.enter("write reports");
    const std::string markdown = eval::markdownReport(reports, config.eval);
    const std::filesystem::path dir(config.eval.output_dir);
    core::StagedOutputs out;
    const auto stage = [&](const std::string& name, const std::string& text) {
        writeText(out.addFile((dir / name).string()), (dir / name).string(), text);
    };
    stage("report.md", markdown);
    stage("report.json", eval::jsonReport(reports, config.eval));
    for (const auto& r : reports) stage(r.sequence.name + "_errors.csv", eval::errorsCsv(r));
    std::vector<core::OptionsSection> sections{{"Eval", &config.eval}};
    for (const auto& s : config.sequences) sections.push_back({s.section, &s.options});
    core::writeEffectiveConfig(out.addFile((dir / "eval_effective.ini").string()), sections,
                               "quasiloc-eval effective configuration (" + cmd.config_path + " + overrides)");
    out.commit();
    timer.leave("write reports");

    std::cout << markdown << "\nReports written to " << dir.string() << "/ (report.md, report.json, "
              << "eval_effective.ini, <sequence>_errors.csv)" << std::endl;
    return 0;
}
}  // namespace

int main(int argc, char** argv) { return quasiloc::core::runProgram(argc, argv, kUsage, run); }
