// quasiloc-localize: global localization of every N-th frame of a stereo rawlog with no initial guess: its left
// image against a database built by quasiloc-build-db (libs/reloc/localizer.h), in the Fast and/or Full budget, and/or
// its raw stereo pair against the LiDAR map by geometry (mode stereo: stereo_queries.h).
//
//     quasiloc-localize <config.ini> [--set Section.key=value]... [--print-timing]
//
// [Localize]: LocalizeRunOptions::declare below. query_image = quasi localizes the quasi-image of the map rendered at
// the ground-truth pose instead of the camera image: a check of the localization machinery without the
// camera-to-map modality gap. Other sections: [Localization] [PointMatching] (and [QuasiImage] for quasi queries).
//
// Other sections: [GeometricLocalization] for mode stereo, [StructureLocalization] for mode structure.
// Outputs in output_dir, all or nothing: queries.txt (every query timestamp), and per mode <mode>.tum (the
// localized queries' T_world_cam0), <mode>.csv (per query: status, reason, inliers, errors, time per stage),
// <mode>_diagnostics.txt (per query: retrieved views with scores and groups, matches, PnP hypotheses), then
// summary.md / summary.json (Recall@{0.1, 0.3, 1.0 m}, mATE, wrong poses, median time per stage) and
// quasiloc-localize.ini (the effective configuration). Ground truth ([Localize] groundtruth) is optional for camera
// queries: without it the outputs carry no errors (summary.json omits recall, mATE and wrong poses) and quasiloc-eval
// scores <mode>.tum against queries.txt afterwards.
#include <mrpt/system/CTimeLogger.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <optional>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/dataset/frame_source.h>
#include <quasiloc/eval/error_stats.h>
#include <quasiloc/eval/json_writer.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <quasiloc/reloc/localizer.h>
#include <quasiloc/reloc/structure_localizer.h>
#include <sstream>

#include "localize_options.h"
#include "localize_report.h"

namespace
{
using namespace quasiloc;
using app::LocalizeRunOptions;
using app::ModeSummary;
using app::QueryImage;
using app::QueryRow;

const char* kUsage =
    "usage: quasiloc-localize <config.ini> [--set Section.key=value]... [--print-timing]\n"
    "Globally localizes every N-th frame of a rawlog: its left image against a quasiloc-build-db database (modes\n"
    "fast, full) and/or its stereo pair against the LiDAR map (mode stereo); writes per-query results, diagnostics\n"
    "and a Recall/mATE summary into [Localize] output_dir.";

/** Every option of the run, loaded and checked. */
struct RunOptions
{
    LocalizeRunOptions run;
    reloc::LocalizerOptions localizer;
    quasi::QuasiOptions quasi;
    reloc::GeometricLocalizationOptions geometric;
    reloc::StructureLocalizerOptions structure;
    std::vector<app::QueryMode> modes;
};

RunOptions loadOptions(const core::CommandLine& cmd)
{
    const auto cfg = core::loadConfig(cmd);
    const std::string name = cmd.config_path;
    RunOptions o;
    core::loadOptionsChecked(o.run, cfg, "Localize", name);
    o.modes = o.run.checkedModes(name);
    core::requireInputFiles(name, "Localize", {{"input_rawlog", o.run.input_rawlog}});
    if (app::needsDatabase(o.modes)) core::requireInputFiles(name, "Localize", {{"database", o.run.database}});
    core::requireInputFiles(
        name, "Localize",
        {{"calibration_ini", o.run.calibration_ini}, {"groundtruth", o.run.groundtruth}, {"map_file", o.run.map_file}},
        false);
    core::loadOptionsChecked(o.localizer, cfg, "Localization", name);
    core::loadOptionsChecked(o.localizer.matching, cfg, "PointMatching", name);
    o.localizer.check(name);
    core::loadOptionsChecked(o.quasi, cfg, "QuasiImage", name);
    o.quasi.check(name);
    core::loadOptionsChecked(o.geometric, cfg, "GeometricLocalization", name);
    o.geometric.check(name);
    core::loadOptionsChecked(o.structure, cfg, "StructureLocalization", name);
    o.structure.check(name);
    return o;
}

/** The queries' results per mode, their diagnostics and the query times. */
struct Queries
{
    std::vector<std::vector<QueryRow>> rows;
    std::vector<std::ostringstream> diagnostics;
    std::ostringstream times;
    int count = 0;
};

QueryRow localizeOne(reloc::Localizer& localizer, const cv::Mat& image, const dataset::StereoFrame& f,
                     const core::CameraModel& camera, reloc::LocalizationMode mode)
{
    QueryRow row;
    row.t = f.timestamp;
    row.report = localizer.localize(image, camera, mode);
    row.has_gt = bool(f.T_world_cam0);
    if (row.has_gt && row.report.localized)
    {
        const auto est = core::fromIsometry(row.report.T_world_cam);
        row.err_m = core::translationDistance(est, *f.T_world_cam0);
        row.err_deg = core::rotationDistanceRad(est, *f.T_world_cam0) * 180 / M_PI;
    }
    return row;
}

/** One query's diagnostics line (`account`: how it was decided) and console line. */
void report(const QueryRow& row, const dataset::StereoFrame& f, const std::string& mode, const std::string& account,
            std::ostream& diagnostics)
{
    const std::string error =
        row.has_gt && row.report.localized ? ", error " + std::to_string(row.err_m) + " m" : std::string();
    diagnostics << "query t=" << std::setprecision(17) << f.timestamp << std::setprecision(6) << " (frame " << f.index
                << ")" << error << ": " << account << "\n";
    std::cout << "t " << std::fixed << std::setprecision(3) << f.timestamp << " " << mode << ": "
              << (row.report.localized ? "localized" : "not localized") << ", inliers " << row.report.inliers << error
              << ", " << row.report.ms.total << " ms" << std::endl;
}

/** A structure query; with ground truth its diagnostics say how far the retrieved guesses were. */
QueryRow localizeStructure(reloc::StructureLocalizer& localizer, const cv::Mat& image, const dataset::StereoFrame& f)
{
    QueryRow row;
    row.t = f.timestamp;
    row.has_gt = bool(f.T_world_cam0);
    const Eigen::Isometry3d truth = row.has_gt ? core::toIsometry(*f.T_world_cam0) : Eigen::Isometry3d::Identity();
    row.report = localizer.localize(image, row.has_gt ? &truth : nullptr);
    if (row.has_gt && row.report.localized)
    {
        row.err_m = core::translationDistance(row.report.T_world_cam, truth);
        row.err_deg = core::rotationDistanceRad(row.report.T_world_cam, truth) * 180 / M_PI;
    }
    return row;
}

/** The structure localizer of mode structure over the database's views (nullptr without it). */
std::unique_ptr<reloc::StructureLocalizer> makeStructureQueries(const RunOptions& o, const reloc::Database* db,
                                                                const map::LidarMap* map,
                                                                const core::CameraModel& camera)
{
    if (!app::hasStructure(o.modes) || !db || !map) return nullptr;
    std::vector<mrpt::poses::CPose3D> views;
    for (const auto& v : db->views) views.push_back(v.T_world_cam);
    auto structure = std::make_unique<reloc::StructureLocalizer>(*map, views, camera, o.quasi, o.structure);
    std::cout << "structure queries against " << o.run.map_file << ": " << structure->summary() << std::endl;
    return structure;
}

/** Per-stage wall time of every query (what --print-timing prints). */
void recordStageTimes(const reloc::LocalizationReport& r, mrpt::system::CTimeLogger& timer)
{
    for (const auto& [stage, ms] : {std::pair<const char*, double>{"query.extract", r.ms.extract},
                                    {"query.retrieval", r.ms.retrieval},
                                    {"query.rerank", r.ms.rerank},
                                    {"query.pnp", r.ms.pnp},
                                    {"query.total", r.ms.total}})
        timer.registerUserMeasure(stage, ms * 1e-3, true);
}

/** The stereo localizer of mode stereo (nullptr without it). */
std::unique_ptr<app::StereoQueries> makeStereoQueries(const RunOptions& o, const core::StereoRig& rig)
{
    if (!app::hasStereo(o.modes)) return nullptr;
    auto stereo = std::make_unique<app::StereoQueries>(o.run.map_file, rig, o.geometric, o.run.gravity,
                                                       o.run.gravity_window_s, o.run.span);
    std::cout << "stereo queries against " << o.run.map_file << ": " << stereo->summary() << std::endl;
    return stereo;
}

Queries localizeQueries(const RunOptions& o, const reloc::Database* db, dataset::FrameSource& source,
                        mrpt::system::CTimeLogger& timer)
{
    const core::CameraModel& camera = source.rig().left;
    std::unique_ptr<map::LidarMap> map;
    std::unique_ptr<quasi::QuasiRenderer> renderer;
    if (o.run.query_image == QueryImage::Quasi || app::hasStructure(o.modes))
        map = std::make_unique<map::LidarMap>(map::LidarMap::load(o.run.map_file));
    if (o.run.query_image == QueryImage::Quasi) renderer = std::make_unique<quasi::QuasiRenderer>(*map, o.quasi);
    std::unique_ptr<reloc::Localizer> localizer;
    if (db) localizer = std::make_unique<reloc::Localizer>(*db, o.localizer);
    const auto stereo = makeStereoQueries(o, source.rig());
    const auto structure = makeStructureQueries(o, db, map.get(), camera);
    Queries out;
    out.rows.resize(o.modes.size());
    out.diagnostics.resize(o.modes.size());
    out.times << "# quasiloc-localize query timestamps (s)\n";
    dataset::StereoFrame f;
    quasi::QuasiImage q;
    while (source.next(f) && (o.run.max_queries == 0 || out.count < o.run.max_queries))
    {
        if (stereo)
            stereo->observe(f, (size_t(o.run.every_n) - f.index % size_t(o.run.every_n)) % size_t(o.run.every_n));
        if (f.index % size_t(o.run.every_n) != 0) continue;
        if (renderer && !f.T_world_cam0) continue;  // nothing to render at
        ++out.count;
        out.times << std::setprecision(17) << f.timestamp << "\n";
        cv::Mat image = f.left;
        if (renderer)
        {
            renderer->render(*f.T_world_cam0, camera, q);
            image = q.gray;
        }
        for (size_t m = 0; m < o.modes.size(); ++m)
        {
            const app::QueryMode& mode = o.modes[m];
            out.rows[m].push_back(mode.stereo      ? stereo->localize(f)
                                  : mode.structure ? localizeStructure(*structure, image, f)
                                                   : localizeOne(*localizer, image, f, camera, mode.budget));
            const std::string account = mode.stereo      ? stereo->describeLast()
                                        : mode.structure ? structure->describeLast()
                                                         : reloc::describe(out.rows[m].back().report, *db);
            report(out.rows[m].back(), f, mode.name, account, out.diagnostics[m]);
            recordStageTimes(out.rows[m].back().report, timer);
        }
    }
    return out;
}

std::string writeOutputs(RunOptions& o, const Queries& queries, const std::string& what)
{
    const std::string& dir = o.run.output_dir;
    core::StagedOutputs out;
    core::writeTextFileAtomically(out.addFile(dir + "/queries.txt"), queries.times.str());
    std::vector<ModeSummary> summaries;
    for (size_t m = 0; m < o.modes.size(); ++m)
    {
        const std::string& mode = o.modes[m].name;
        core::Trajectory traj;
        traj.header = "quasiloc-localize " + mode + ": T_world_cam0 of the localized queries";
        for (const auto& r : queries.rows[m])
            if (r.report.localized) traj.poses.push_back({r.t, core::fromIsometry(r.report.T_world_cam)});
        core::writeTum(out.addFile(dir + "/" + mode + ".tum"), traj);
        core::writeTextFileAtomically(out.addFile(dir + "/" + mode + ".csv"), app::csvOf(queries.rows[m]));
        core::writeTextFileAtomically(out.addFile(dir + "/" + mode + "_diagnostics.txt"), queries.diagnostics[m].str());
        summaries.push_back(app::summarize(mode, queries.rows[m]));
    }
    const std::string md = app::markdownOf(summaries, what);
    core::writeTextFileAtomically(out.addFile(dir + "/summary.md"), md);
    core::writeTextFileAtomically(out.addFile(dir + "/summary.json"), app::jsonOf(summaries, what));
    core::writeEffectiveConfig(out.addFile(dir + "/quasiloc-localize.ini"),
                               {{"Localize", &o.run},
                                {"Localization", &o.localizer},
                                {"PointMatching", &o.localizer.matching},
                                {"QuasiImage", &o.quasi},
                                {"GeometricLocalization", &o.geometric},
                                {"StructureLocalization", &o.structure}},
                               "quasiloc-localize effective configuration");
    out.commit();
    return md;
}

bool anyGroundTruth(const Queries& queries)
{
    for (const auto& mode : queries.rows)
        for (const QueryRow& r : mode)
            if (r.has_gt) return true;
    return false;
}

/** The one line saying that no error was computed, why, and how to score the queries afterwards. */
std::string noGroundTruthLine(const RunOptions& o, const std::string& mode)
{
    const std::string& dir = o.run.output_dir;
    return std::string("errors      none: ") +
           (o.run.groundtruth.empty() ? "no ground truth given ([Localize] groundtruth)"
                                      : "no query has a pose of " + o.run.groundtruth + " within 5 ms") +
           "; to score the queries: quasiloc-eval --kind localization --estimate " + dir + "/" + mode +
           ".tum --queries " + dir + "/queries.txt --groundtruth <TUM of T_world_cam0>";
}

/** What was localized against what, for the summary's head. */
std::string queriesDescription(const RunOptions& o, const reloc::Database* db, const std::string& image)
{
    std::string what;
    if (db)
        what = "database " + o.run.database + " (" + db->summary() + "); queries: every " +
               std::to_string(o.run.every_n) + "th left " + image + " of " + o.run.input_rawlog;
    if (app::hasStereo(o.modes))
        what += std::string(db ? "\n\n" : "") + "mode stereo: every " + std::to_string(o.run.every_n) +
                "th raw stereo pair of " + o.run.input_rawlog + " against the map " + o.run.map_file + ", up from " +
                (o.run.gravity == app::QueryGravity::Imu ? "the IMU" : "a level camera") +
                "; its stage columns: extract = stereo matching, retrieval = place retrieval, rerank = coarse "
                "search, PnP = refinement and polish; inliers = stereo points the map explains";
    return what;
}

int run(const core::CommandLine& cmd)
{
    RunOptions o = loadOptions(cmd);
    std::optional<reloc::Database> db;
    if (app::needsDatabase(o.modes))
    {
        db = reloc::Database::load(o.run.database);
        std::cout << "database " << o.run.database << ": " << db->summary() << std::endl;
    }
    dataset::FrameSourceOptions so;
    so.groundtruth_tum = o.run.groundtruth;
    so.calibration_ini = o.run.calibration_ini;
    auto source = dataset::openRawlog(o.run.input_rawlog, so);
    mrpt::system::CTimeLogger timer(true, "quasiloc-localize");
    const Queries queries = localizeQueries(o, db ? &*db : nullptr, *source, timer);
    core::require(queries.count > 0, o.run.input_rawlog,
                  "no query frame (check every_n, and ground truth for query_image = quasi)");
    const std::string image =
        o.run.query_image == QueryImage::Camera ? "camera image" : "quasi-image at the ground-truth pose";
    const std::string what = queriesDescription(o, db ? &*db : nullptr, image);
    const std::string md = writeOutputs(o, queries, what);
    std::cout << "\n" << md << "outputs in " << o.run.output_dir << std::endl;
    if (!anyGroundTruth(queries)) std::cout << noGroundTruthLine(o, o.modes.front().name) << std::endl;
    if (cmd.print_timing) std::cout << timer.getStatsAsText();
    timer.clear(true);  // CTimeLogger prints what it holds when destroyed
    return 0;
}
}  // namespace

int main(int argc, char** argv) { return core::runProgram(argc, argv, kUsage, run); }
