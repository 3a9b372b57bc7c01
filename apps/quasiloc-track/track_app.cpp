// quasiloc-track's run (track_app.h): options -> session -> outputs.
#include <iostream>
#include <sstream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/dataset/calibration.h>
#include <quasiloc/dataset/frame_source.h>
#include <quasiloc/tracking/test_harness.h>
#include <quasiloc/tracking/tracking_session.h>

#include "scene_export.h"
#include "track_app.h"

namespace
{
using namespace quasiloc;

/** The product refuses the harness's sections: a kidnap or a fault asked of it would otherwise be ignored. */
void refuseHarnessSections(const mrpt::config::CConfigFileBase& cfg, const std::string& config_name)
{
    for (const core::OptionsSection& harness : tracking::HarnessOptions().sections())
    {
        const std::string& section = harness.section;
        std::vector<std::string> keys;
        if (cfg.sectionExists(section)) cfg.getAllKeys(section, keys);
        core::require(keys.empty(), config_name + ": [" + section + "] " + (keys.empty() ? "" : keys.front()),
                      "is a test harness's key: run quasiloc-track-harness (docs/reliability.md)");
    }
}

tracking::SessionOptions loadOptions(const core::CommandLine& cmd, bool harness,
                                     tracking::HarnessOptions& harness_options)
{
    const auto cfg = core::loadConfig(cmd);
    tracking::SessionOptions o;
    o.load(cfg, cmd.config_path);
    if (harness)
        harness_options.load(cfg, cmd.config_path);
    else
        refuseHarnessSections(cfg, cmd.config_path);
    const tracking::TrackingRunOptions& t = o.tracker;
    core::requireInputFiles(
        cmd.config_path, "Tracking",
        {{"input_rawlog", t.input_rawlog}, {"calibration_ini", t.calibration_ini}, {"map_file", t.map_file}});
    core::require(!t.groundtruth.empty() || t.initialization.init != tracking::InitMode::GroundTruth,
                  cmd.config_path + ": [Tracking] groundtruth",
                  "is required with [Initialization] init = groundtruth (the start is taken from it); without ground "
                  "truth, set init = global (global localization in the map, no initial guess)");
    core::requireInputFiles(cmd.config_path, "Tracking", {{"groundtruth", t.groundtruth}}, /*required=*/false);
    return o;
}

void writeOutputs(const tracking::SessionOptions& o, const tracking::HarnessOptions* harness,
                  const tracking::TrackingSession& session, const tracking::SessionSummary& summary,
                  const map::LidarMap& map)
{
    const std::string& dir = o.tracker.output_dir;
    const tracking::RunLog& log = session.log();
    core::StagedOutputs out;
    core::writeTum(out.addFile(dir + "/trajectory.tum"), log.estimate());
    if (o.tracker.write_scene)
        app::writeTrackingScene(out.addFile(dir + "/scene.3Dscene"), map, log.groundTruth(), log.estimate());
    core::writeTextFileAtomically(out.addFile(dir + "/diagnostics.csv"), log.csv());
    core::writeTextFileAtomically(out.addFile(dir + "/summary.json"), log.summaryJson(summary));
    if (session.hasStarter())
        core::writeTextFileAtomically(out.addFile(dir + "/initialization.txt"), session.initializationRecord());
    auto sections = o.sections();
    if (harness)
        for (const core::OptionsSection& s : harness->sections()) sections.push_back(s);
    core::writeEffectiveConfig(out.addFile(dir + "/quasiloc-track.ini"), sections,
                               "quasiloc-track effective configuration");
    out.commit();
    std::cout << "outputs     " << dir << "/{trajectory.tum,diagnostics.csv,summary.json,quasiloc-track.ini"
              << (session.hasStarter() ? ",initialization.txt" : "") << (o.tracker.write_scene ? ",scene.3Dscene" : "")
              << "}" << std::endl;
}

/** The one line that replaces the ATE when no logged pose has ground truth: why, and how to score the run later
 *  (quasiloc-eval looking the ground truth up as the frame source does, so that it prints the ATE this run would). */
std::string noGroundTruthLine(const tracking::TrackingRunOptions& t, double max_gt_dt_s)
{
    std::ostringstream o;
    o << "ATE         none: ";
    if (t.groundtruth.empty())
        o << "no ground truth given ([Tracking] groundtruth)";
    else
        o << "no logged pose has a pose of " << t.groundtruth << " within " << max_gt_dt_s << " s (another time base?)";
    o << "; to score the run: quasiloc-eval --estimate " << t.output_dir
      << "/trajectory.tum --groundtruth <TUM of T_world_cam0> --association interpolated --max-dt-s " << max_gt_dt_s;
    return o.str();
}

}  // namespace

namespace quasiloc::app
{
int runTrack(const core::CommandLine& cmd, bool harness)
{
    tracking::HarnessOptions harness_options;
    const tracking::SessionOptions o = loadOptions(cmd, harness, harness_options);
    const tracking::TrackingRunOptions& t = o.tracker;
    tracking::MapContext context(t.map_file, o.quasi);
    dataset::FrameSourceOptions so;
    so.groundtruth_tum = t.groundtruth;
    so.calibration_ini = t.calibration_ini;
    std::unique_ptr<dataset::FrameSource> source = dataset::openRawlog(t.input_rawlog, so);
    // The harness's faults live in the data the session reads.
    if (harness) source = tracking::withFaults(std::move(source), harness_options.faults);
    const dataset::SensorCalibration calibration = dataset::loadCalibration(t.calibration_ini);
    std::cout << "map " << context.map().summary() << "\n" << source->description() << std::endl;
    tracking::TrackingSession session(o, context, *source, calibration.requireImu(t.calibration_ini), std::cout);
    if (harness) tracking::applyHarness(harness_options, session, std::cout);
    const tracking::SessionSummary summary = session.run(t.input_rawlog);
    for (const std::string& w : source->warnings()) std::cout << "warning     " << w << "\n";
    std::cout << session.log().summary(summary);
    if (!session.log().hasGroundTruth()) std::cout << noGroundTruthLine(t, so.max_gt_dt_s) << std::endl;
    writeOutputs(o, harness ? &harness_options : nullptr, session, summary, context.map());
    if (cmd.print_timing) std::cout << session.timing();
    return 0;
}
}  // namespace quasiloc::app
