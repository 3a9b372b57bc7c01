// quasiloc-eval: trajectory (ATE/RPE) and localization-query (recall/mATE) evaluation against ground truth.
//
//     quasiloc-eval --estimate <TUM> --groundtruth <TUM> [--<Eval key> value]... [--set Section.key=value]...
//     quasiloc-eval <config.ini> [--set Eval.key=value]... [--set Eval.<name>.key=value]... [--print-timing]
//
// The first form evaluates one trajectory without an INI (--kind localization and --queries <file>: one localizer's
// queries): every other "--some-key value" is the [Eval] key some_key (--output-dir, --max-dt-s, --association,
// --align, --rpe-delta-m, --rpe-delta-s, --rpe-delta-frames), and --name names the sequence (default: the estimate's
// file name without extension).
// INI (full description in libs/eval/include/quasiloc/eval/eval_config.h; example: share/quasiloc/eval_example.ini):
//   [Eval]  output_dir, max_dt_s (0.02), association = nearest|interpolated, align = none|se3|sim3 (none: the
//           estimate the RPE is computed on), rpe_delta_m (1.0), rpe_delta_s (1.0), rpe_delta_frames (0),
//           recall_thresholds_m ([0.1 0.3 1.0]), recall_thresholds_deg ([] = translation only),
//           sequence_names = [a b]
//   [Eval.a] kind = tracking|localization, estimate = <TUM>, groundtruth = <TUM>, queries = <timestamp list>
// Estimate and ground truth are TUM files (t tx ty tz qx qy qz qw) of T_map_cam. A localization estimate holds
// the localized queries only; `queries` lists every queried timestamp (one per line, '#' comments; the first
// column of a CSV/TUM also works), so that not-localized queries count as failures in the recall.
//
// Outputs in output_dir, written atomically (all or nothing): report.md (also printed to stdout),
// report.json, eval_effective.ini, <sequence>_errors.csv (per pose / per query errors).
// A tracking sequence gets the ATE in the map frame (unaligned) first, then after SE(3) and Sim(3) alignment, then the
// RPE per metre / second / poses.
#include <mrpt/system/CTimeLogger.h>

#include <algorithm>
#include <cctype>
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
    "usage: quasiloc-eval --estimate <TUM> --groundtruth <TUM> [--kind tracking|localization] [--queries FILE]\n"
    "                     [--name NAME] [--output-dir DIR] [--max-dt-s S]\n"
    "                     [--association nearest|interpolated] [--align none|se3|sim3] [--rpe-delta-m M]\n"
    "                     [--rpe-delta-s S] [--rpe-delta-frames N] [--print-timing]\n"
    "       quasiloc-eval <config.ini> [--set Eval.key=value]... [--set Eval.<sequence>.key=value]... "
    "[--print-timing]\n"
    "Evaluates estimated trajectories (ATE unaligned, SE(3)- and Sim(3)-aligned; RPE per metre and per second) and\n"
    "localization queries against ground truth (docs/quasiloc-eval.md, share/quasiloc/eval_example.ini).";

/** A sequence name from a file name: its stem, with anything but letters, digits, '_' and '-' made '_'. */
std::string nameFromPath(const std::string& path)
{
    std::string n = std::filesystem::path(path).stem().string();
    for (char& c : n)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') c = '_';
    return n.empty() ? "estimate" : n;
}

/** The command line of the INI-less form as the INI form's: --estimate/--groundtruth/--name (and --kind, --queries)
 *  make the one sequence, every other "--key-name value" becomes the override Eval.key_name=value; the user's --set
 *  come last. */
quasiloc::core::CommandLine fromFlags(const quasiloc::core::CommandLine& cmd)
{
    using quasiloc::core::require;
    std::string estimate, groundtruth, name;
    std::vector<std::pair<std::string, std::string>> eval_keys, sequence_keys;
    for (size_t i = 0; i < cmd.flags.size(); ++i)
    {
        const std::string& f = cmd.flags[i];
        require(f.size() > 2 && f.rfind("--", 0) == 0, "command line",
                "unexpected argument '" + f + "' (an INI file comes first, or use --estimate and --groundtruth)");
        require(i + 1 < cmd.flags.size(), "command line (" + f + ")", "needs a value");
        const std::string value = cmd.flags[++i];
        std::string key = f.substr(2);
        std::replace(key.begin(), key.end(), '-', '_');
        if (key == "estimate")
            estimate = value;
        else if (key == "groundtruth")
            groundtruth = value;
        else if (key == "name")
            name = value;
        else if (key == "kind" || key == "queries")
            sequence_keys.emplace_back(key, value);
        else
            eval_keys.emplace_back("Eval." + key, value);
    }
    require(!estimate.empty(), "command line", "--estimate <TUM> is required (or give an INI file)");
    require(!groundtruth.empty(), "command line", "--groundtruth <TUM> is required (or give an INI file)");
    if (name.empty()) name = nameFromPath(estimate);
    quasiloc::core::CommandLine out = cmd;
    out.flags.clear();
    out.overrides = {{"Eval.sequence_names", "[" + name + "]"},
                     {"Eval." + name + ".estimate", estimate},
                     {"Eval." + name + ".groundtruth", groundtruth}};
    for (const auto& [key, value] : sequence_keys) out.overrides.emplace_back("Eval." + name + "." + key, value);
    out.overrides.insert(out.overrides.end(), eval_keys.begin(), eval_keys.end());
    out.overrides.insert(out.overrides.end(), cmd.overrides.begin(), cmd.overrides.end());
    return out;
}

void writeText(const std::string& path, const std::string& final_name, const std::string& text)
{
    std::ofstream f(path);
    quasiloc::core::require(f.good(), final_name, "cannot open for writing");
    f << text;
    f.close();
    quasiloc::core::require(!f.fail(), final_name, "write failed");
}

int run(const quasiloc::core::CommandLine& cmd_in)
{
    using namespace quasiloc;
    // An INI file, when given, comes first; otherwise the flags describe the one trajectory.
    core::CommandLine cmd = cmd_in;
    if (!cmd.flags.empty() && cmd.flags[0].rfind("--", 0) != 0)
    {
        cmd.config_path = cmd.flags[0];
        cmd.flags.erase(cmd.flags.begin());
        if (!cmd.flags.empty())
            core::require(false, "command line",
                          "unexpected argument '" + cmd.flags[0] + "' after the INI file (use --set Eval.key=value)");
    }
    else
        cmd = fromFlags(cmd);
    const std::string config_name = cmd.config_path.empty() ? "command line" : cmd.config_path;
    mrpt::system::CTimeLogger timer(cmd.print_timing, "quasiloc-eval");
    const auto cfg = core::loadConfig(cmd);
    const eval::EvalConfig config = eval::loadEvalConfig(cfg, config_name);

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
                               "quasiloc-eval effective configuration (" + config_name + " + overrides)");
    out.commit();
    timer.leave("write reports");

    std::cout << markdown << "\nReports written to " << dir.string() << "/ (report.md, report.json, "
              << "eval_effective.ini, <sequence>_errors.csv)" << std::endl;
    return 0;
}
}  // namespace

int main(int argc, char** argv)
{
    return quasiloc::core::runProgram(argc, argv, kUsage, run, /*config_required=*/false);
}
