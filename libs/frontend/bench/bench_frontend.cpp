// bench_frontend: how well the source-agnostic front-end matches, and how fast.
//   bench_frontend [config.ini] [--set Section.key=value]... [--print-timing]
// Part 1 (simulated sequences, simulated here with the sim library unless [Bench] sim_dirs names existing
// sim-rawlog folders): camera <-> quasi-image point and line matches at the ground-truth pose and at a pose
// perturbed by 10 cm / 2 deg, count and precision, for every point extractor; association statistics; with
// libtorch and the model files, XFeat + LighterGlue against XFeat + mutual nearest neighbour.
// Part 2 (the real EuRoC micro frames): temporal and stereo match counts and inlier ratios.
// Timing per stage with the budgets (752x480, 2 cores, Release, classical): points + lines <= 15 ms per image,
// matching <= 5 ms per pair, associations <= 2 ms. Sections: [Bench] (bench_common.h), the front-end's
// ([Features] ... [Stereo], frontend.h) and [QuasiImage]. Every bound is printed next to the measured value.
#include <mrpt/config/CConfigFileMemory.h>

#include <iostream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/core/staged_output.h>
#include <sstream>
#include <sys/stat.h>

#include "bench_common.h"

namespace quasiloc::bench
{
void BenchOptions::declare(core::OptionTable& t)
{
    using core::Range;
    t.add("extractors", extractors, "comma-separated [Features] types (xfeat is skipped without a model file)");
    t.add("xfeat_model_path", xfeat_model_path, "XFeat ONNX file");
    t.add("lighterglue_model", lighterglue_model, "LighterGlue TorchScript file (measured when it exists)");
    t.add("sim_dirs", sim_dirs, "existing sim-rawlog folders (comma separated); empty: simulate sim_worlds");
    t.add("sim_worlds", sim_worlds, "simulation INI files (comma separated)");
    t.add("sim_root", sim_root, "where the simulated sequences go (reused when complete)");
    t.add("sim_duration_s", sim_duration_s, "s", Range::above(0), "simulated duration");
    t.add("sim_start_offset_s", sim_start_offset_s, "s", Range::any(), "skip the take-off");
    t.add("frames_per_sequence", frames_per_sequence, "", Range::atLeast(1), "frames evenly spread over a sequence");
    t.add("precision_px", precision_px, "px", Range::above(0), "a camera<->quasi match is correct within this");
    t.add("perturb_translation_m", perturb_translation_m, "m", Range::any(), "perturbation of the rendering pose");
    t.add("perturb_rotation_deg", perturb_rotation_deg, "deg", Range::any(), "perturbation of the rendering pose");
    t.add("cross_modal_window_px", cross_modal_window_px, "px", Range::above(0),
          "search window of camera<->quasi point matching");
    t.add("euroc_dir", euroc_dir, "EuRoC micro folder");
    t.add("euroc_frames", euroc_frames, "", Range::atLeast(2), "EuRoC frames used");
    t.add("static_inlier_px", static_inlier_px, "px", Range::above(0), "static scene: a temporal match moved less");
    t.add("ransac_px", ransac_px, "px", Range::above(0), "fundamental-matrix RANSAC threshold");
    t.add("report_path", report_path, "optional Markdown copy of the tables");
}

void BenchOptions::check(const std::string& input) const
{
    core::require(!extractorList().empty(), input + ": [Bench] extractors", "no extractor named");
    for (const auto& e : extractorList())
        core::require(e == "orb" || e == "sift" || e == "akaze" || e == "xfeat", input + ": [Bench] extractors",
                      "'" + e + "' is not one of orb, sift, akaze, xfeat");
}

std::vector<std::string> BenchOptions::extractorList() const
{
    std::vector<std::string> out;
    std::stringstream ss(extractors);
    for (std::string e; std::getline(ss, e, ',');)
    {
        e.erase(0, e.find_first_not_of(" \t"));
        e.erase(e.find_last_not_of(" \t") + 1);
        if (!e.empty()) out.push_back(e);
    }
    return out;
}

void StageTimes::add(const std::string& stage, double ms)
{
    auto& s = stats_[stage];
    s.sum += ms, s.max = std::max(s.max, ms), ++s.n;
    logger_.registerUserMeasure(stage, ms * 1e-3, true);
}

frontend::FrontendOptions withExtractor(const frontend::FrontendOptions& base, const std::string& type,
                                        const BenchOptions& bench)
{
    frontend::FrontendOptions o = base;
    bool known = false;
    for (const auto& [name, t] : frontend::featureTypeNames())
        if (name == type) o.features.type = t, known = true;
    core::require(known, "extractors", "'" + type + "' is not a [Features] type");
    if (type == "xfeat" && o.features.xfeat_model_path.empty()) o.features.xfeat_model_path = bench.xfeat_model_path;
    return o;
}

void Report::line(const std::string& s)
{
    std::cout << s << std::endl;
    text += s + "\n";
}

std::string fmt(double v, int decimals)
{
    std::ostringstream os;
    os.setf(std::ios::fixed);
    os.precision(decimals);
    os << v;
    return os.str();
}

std::string pct(double num, double den) { return den > 0 ? fmt(100.0 * num / den, 1) + " %" : "-"; }

std::string budgetFor(const std::string& stage, double mean_ms)
{
    if (stage.find("xfeat") != std::string::npos) return "-";  // budgets are for the classical front-end
    double bound = -1;
    // Per image, camera images and quasi-images alike ("points + lines per image", "extract ... (points + lines)").
    if (stage.find("points + lines") != std::string::npos)
        bound = 15;
    else if (stage.find("match points") != std::string::npos || stage.find("match lines") != std::string::npos)
        bound = 5;
    else if (stage.find("associations") != std::string::npos)
        bound = 2;
    if (bound < 0) return "-";
    return "<= " + fmt(bound, 0) + (mean_ms <= bound ? " (met)" : " (MISSED)");
}
}  // namespace quasiloc::bench

namespace
{
const char* kUsage =
    "Usage: bench_frontend [config.ini] [--set Section.key=value]... [--print-timing]\n"
    "Measures the front-end: camera<->quasi matching on simulated sequences (gt and perturbed pose), temporal\n"
    "and stereo matching on the real EuRoC micro frames, timing per stage against the budgets.\n"
    "Sections: [Bench], [Features], [PointMatching], [Lines], [LineMatching], [Association], [Stereo], [QuasiImage].\n"
    "Run from the repository root (relative paths, e.g. the sim world INIs, are relative to it).";

int run(const quasiloc::core::CommandLine& cmd_in)
{
    using namespace quasiloc;
    // The INI file is optional: the first plain argument, if any.
    const core::CommandLine cmd = core::withOptionalConfig(cmd_in);
    const mrpt::config::CConfigFileMemory cfg = core::loadConfig(cmd);  // overrides alone without an INI file
    const std::string name = cmd.config_path.empty() ? "command line" : cmd.config_path;
    bench::BenchOptions bench;
    core::loadOptionsChecked(bench, cfg, "Bench", name);
    bench.check(name);
    frontend::FrontendOptions fe;
    fe.load(cfg, name);
    quasi::QuasiOptions qo;
    core::loadOptionsChecked(qo, cfg, "QuasiImage", name);
    qo.check(name);

    mrpt::system::CTimeLogger logger(cmd.print_timing, "bench_frontend");
    bench::Report report;
    report.line("# bench_frontend");
    report.line("");
    bench::runCrossModal(cfg, bench, fe, qo, logger, report);
    bench::runEuroc(bench, fe, logger, report);
    if (!bench.report_path.empty())
    {
        core::StagedOutputs out;
        core::writeTextFileAtomically(out.addFile(bench.report_path), report.text);
        auto sections = fe.sections();
        sections.push_back({"Bench", &bench});
        sections.push_back({"QuasiImage", &qo});
        core::writeEffectiveConfig(out.addFile(bench.report_path + ".ini"), sections,
                                   "bench_frontend effective configuration");
        out.commit();
        std::cout << "report written to " << bench.report_path << std::endl;
    }
    return 0;
}
}  // namespace

int main(int argc, char** argv) { return quasiloc::core::runProgram(argc, argv, kUsage, run, false); }
