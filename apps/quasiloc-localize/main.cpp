// quasiloc-localize: global localization of the left images of a stereo rawlog, every N frames, against a
// database built by quasiloc-build-db (libs/reloc/localizer.h), in the Fast and/or Full budget.
//
//     quasiloc-localize <config.ini> [--set Section.key=value]... [--print-timing]
//
// [Localize]: LocalizeRunOptions::declare below. query_image = quasi localizes the quasi-image of the map rendered at
// the ground-truth pose instead of the camera image: a check of the localization machinery without the
// camera-to-map modality gap. Other sections: [Localization] [PointMatching] (and [QuasiImage] for quasi queries).
//
// Outputs in output_dir, all or nothing: queries.txt (every query timestamp), and per mode <mode>.tum (the
// localized queries' T_world_cam0), <mode>.csv (per query: status, reason, inliers, errors, time per stage),
// <mode>_diagnostics.txt (per query: retrieved views with scores and groups, matches, PnP hypotheses), then
// summary.md / summary.json (Recall@{0.1, 0.3, 1.0 m}, mATE, wrong poses, median time per stage) and
// quasiloc-localize.ini (the effective configuration).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
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
#include <sstream>

namespace
{
using namespace quasiloc;

/** What is localized: the camera's left image, or the quasi-image rendered at the ground-truth pose. */
enum class QueryImage
{
    Camera,
    Quasi
};

struct LocalizeRunOptions : public core::DeclaredOptions
{
    std::string database, input_rawlog, calibration_ini, groundtruth, map_file, output_dir = "out/localize";
    std::vector<std::string> modes{"fast", "full"};
    QueryImage query_image = QueryImage::Camera;
    int every_n = 10, max_queries = 0;

    void declare(core::OptionTable& t) override
    {
        t.add("database", database, "the database (quasiloc-build-db)");
        t.add("input_rawlog", input_rawlog, "the stereo rawlog whose left images are queried");
        t.add("calibration_ini", calibration_ini, "optional: overrides the rawlog's calibration");
        t.add("groundtruth", groundtruth, "optional TUM of T_world_cam0, for the error table");
        t.add("map_file", map_file, "the LiDAR map (query_image = quasi)");
        t.add("output_dir", output_dir, "where the outputs go");
        t.add("modes", modes, "fast, full or both");
        t.addEnum("query_image", query_image, {{"camera", QueryImage::Camera}, {"quasi", QueryImage::Quasi}},
                  "the camera's left image, or the quasi-image rendered at the ground-truth pose");
        t.add("every_n", every_n, "", core::Range::atLeast(1), "query every N-th frame");
        t.add("max_queries", max_queries, "", core::Range::atLeast(0), "queries at most (0: all)");
    }

    /** The budgets of `modes`; InputError naming `name` for a quasi query without map and ground truth, or no
     *  or an unknown mode. */
    std::vector<reloc::LocalizationMode> checkedModes(const std::string& name) const
    {
        const std::string key = name + ": [Localize] ";
        core::require(query_image == QueryImage::Camera || (!map_file.empty() && !groundtruth.empty()),
                      key + "query_image",
                      "quasi needs map_file and groundtruth (the query is rendered at the ground-truth pose)");
        std::vector<reloc::LocalizationMode> out;
        for (const auto& m : modes) out.push_back(reloc::localizationModeFromString(m, key + "modes"));
        core::require(!out.empty(), key + "modes", "needs fast, full or both");
        return out;
    }
};

struct QueryRow
{
    double t = 0;
    reloc::LocalizationReport report;
    bool has_gt = false;
    double err_m = NAN, err_deg = NAN;
};

const double kThresholds[] = {0.1, 0.3, 1.0};

struct ModeSummary
{
    std::string mode;
    size_t queries = 0, evaluated = 0, localized = 0, wrong = 0;  ///< wrong: localized but > 1 m off
    double recall[3] = {0, 0, 0};
    eval::ErrorStats ate_m, ms_total, ms_extract, ms_retrieval, ms_rerank, ms_pnp;
};

ModeSummary summarize(const std::string& mode, const std::vector<QueryRow>& rows)
{
    ModeSummary s;
    s.mode = mode;
    s.queries = rows.size();
    std::vector<double> ate, tot, ex, re, rr, pnp;
    size_t within[3] = {0, 0, 0};
    for (const auto& q : rows)
    {
        tot.push_back(q.report.ms.total);
        ex.push_back(q.report.ms.extract);
        re.push_back(q.report.ms.retrieval);
        rr.push_back(q.report.ms.rerank);
        pnp.push_back(q.report.ms.pnp);
        if (!q.has_gt) continue;
        ++s.evaluated;
        if (!q.report.localized) continue;
        ++s.localized;
        for (int k = 0; k < 3; ++k) within[k] += q.err_m <= kThresholds[k] ? 1 : 0;
        if (q.err_m <= kThresholds[2]) ate.push_back(q.err_m);
        else ++s.wrong;
    }
    for (int k = 0; k < 3; ++k) s.recall[k] = s.evaluated ? 100.0 * double(within[k]) / double(s.evaluated) : NAN;
    s.ate_m = eval::computeStats(ate);
    s.ms_total = eval::computeStats(tot);
    s.ms_extract = eval::computeStats(ex);
    s.ms_retrieval = eval::computeStats(re);
    s.ms_rerank = eval::computeStats(rr);
    s.ms_pnp = eval::computeStats(pnp);
    return s;
}

std::string csvOf(const std::vector<QueryRow>& rows)
{
    std::ostringstream csv;
    csv << "t,localized,reason,inliers,correspondences,retried,groups_reranked,err_m,err_deg,ms_extract,ms_retrieval,"
           "ms_rerank,ms_pnp,ms_total\n";
    for (const auto& q : rows)
    {
        const auto& r = q.report;
        int reranked = 0;
        for (const auto& g : r.groups) reranked += g.matched >= 0 ? 1 : 0;
        std::string reason = r.reason;
        std::replace(reason.begin(), reason.end(), ',', ';');
        csv << std::setprecision(17) << q.t << std::setprecision(6) << "," << r.localized << "," << reason << ","
            << r.inliers << "," << r.correspondences << "," << r.retried << "," << reranked << "," << q.err_m << ","
            << q.err_deg << "," << r.ms.extract << "," << r.ms.retrieval << "," << r.ms.rerank << "," << r.ms.pnp
            << "," << r.ms.total << "\n";
    }
    return csv.str();
}

std::string markdownOf(const std::vector<ModeSummary>& modes, const std::string& what)
{
    std::ostringstream md;
    md << std::fixed << std::setprecision(1) << "# quasiloc-localize summary\n\n" << what << "\n\n"
       << "| mode | queries | localized | Recall@0.1 m | Recall@0.3 m | Recall@1.0 m | mATE (<= 1 m) [cm] | wrong (> 1 m) "
          "| median ms | p-max ms | extract | retrieval | rerank | PnP |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& s : modes)
        md << "| " << s.mode << " | " << s.evaluated << " | " << s.localized << " | " << s.recall[0] << " % | "
           << s.recall[1] << " % | " << s.recall[2] << " % | " << 100 * s.ate_m.mean << " | " << s.wrong << " | "
           << s.ms_total.median << " | " << s.ms_total.max << " | " << s.ms_extract.median << " | "
           << s.ms_retrieval.median << " | " << s.ms_rerank.median << " | " << s.ms_pnp.median << " |\n";
    md << "\nRecall = localized within the threshold / queries with ground truth (not-localized queries count). mATE: "
          "mean translation error of the queries localized within 1 m. Stage times are medians (ms, wall).\n";
    return md.str();
}

std::string jsonOf(const std::vector<ModeSummary>& modes, const std::string& what)
{
    eval::JsonWriter j;
    j.beginObject().key("what").value(what).key("modes").beginArray();
    for (const auto& s : modes)
    {
        j.beginObject().key("mode").value(s.mode).key("queries").value(s.queries).key("evaluated").value(s.evaluated);
        j.key("localized").value(s.localized).key("wrong_over_1m").value(s.wrong);
        j.key("recall_0.1m").value(s.recall[0]).key("recall_0.3m").value(s.recall[1]).key("recall_1.0m").value(s.recall[2]);
        j.key("mate_m").value(s.ate_m.mean).key("median_ms").value(s.ms_total.median).key("max_ms").value(s.ms_total.max);
        j.key("median_ms_extract").value(s.ms_extract.median).key("median_ms_retrieval").value(s.ms_retrieval.median);
        j.key("median_ms_rerank").value(s.ms_rerank.median).key("median_ms_pnp").value(s.ms_pnp.median);
        j.endObject();
    }
    j.endArray().endObject();
    return j.str() + "\n";
}

const char* kUsage =
    "usage: quasiloc-localize <config.ini> [--set Section.key=value]... [--print-timing]\n"
    "Globally localizes every N-th left image of a rawlog against a quasiloc-build-db database; writes per-query\n"
    "results, diagnostics and a Recall/mATE summary into [Localize] output_dir.";

int run(const core::CommandLine& cmd)
{
    const auto cfg = core::loadConfig(cmd);
    const std::string name = cmd.config_path;
    LocalizeRunOptions o;
    core::loadOptionsChecked(o, cfg, "Localize", name);
    core::requireInputFiles(name, "Localize", {{"database", o.database}, {"input_rawlog", o.input_rawlog}});
    core::requireInputFiles(name, "Localize",
                            {{"calibration_ini", o.calibration_ini}, {"groundtruth", o.groundtruth}, {"map_file", o.map_file}},
                            false);
    const std::vector<reloc::LocalizationMode> modes = o.checkedModes(name);
    reloc::LocalizerOptions lo;
    core::loadOptionsChecked(lo, cfg, "Localization", name);
    core::loadOptionsChecked(lo.matching, cfg, "PointMatching", name);
    lo.check(name);
    quasi::QuasiOptions qo;
    core::loadOptionsChecked(qo, cfg, "QuasiImage", name);
    qo.check(name);

    const reloc::Database db = reloc::Database::load(o.database);
    std::cout << "database " << o.database << ": " << db.summary() << std::endl;
    dataset::FrameSourceOptions so;
    so.groundtruth_tum = o.groundtruth;
    so.calibration_ini = o.calibration_ini;
    auto source = dataset::openRawlog(o.input_rawlog, so);
    const core::CameraModel& camera = source->rig().left;
    std::unique_ptr<map::LidarMap> map;
    std::unique_ptr<quasi::QuasiRenderer> renderer;
    if (o.query_image == QueryImage::Quasi)
    {
        map = std::make_unique<map::LidarMap>(map::LidarMap::load(o.map_file));
        renderer = std::make_unique<quasi::QuasiRenderer>(*map, qo);
    }
    reloc::Localizer localizer(db, lo);

    std::vector<std::vector<QueryRow>> rows(modes.size());
    std::vector<std::ostringstream> diag(modes.size());
    std::ostringstream query_times;
    query_times << "# quasiloc-localize query timestamps (s)\n";
    dataset::StereoFrame f;
    quasi::QuasiImage q;
    int count = 0;
    while (source->next(f) && (o.max_queries == 0 || count < o.max_queries))
    {
        if (f.index % size_t(o.every_n) != 0) continue;
        if (o.query_image == QueryImage::Quasi && !f.T_world_cam0) continue;  // nothing to render at
        ++count;
        query_times << std::setprecision(17) << f.timestamp << "\n";
        cv::Mat image = f.left;
        if (renderer)
        {
            renderer->render(*f.T_world_cam0, camera, q);
            image = q.gray;
        }
        for (size_t m = 0; m < modes.size(); ++m)
        {
            QueryRow row;
            row.t = f.timestamp;
            row.report = localizer.localize(image, camera, modes[m]);
            if (f.T_world_cam0)
            {
                row.has_gt = true;
                if (row.report.localized)
                {
                    const auto est = core::fromIsometry(row.report.T_world_cam);
                    row.err_m = core::translationDistance(est, *f.T_world_cam0);
                    row.err_deg = core::rotationDistanceRad(est, *f.T_world_cam0) * 180 / M_PI;
                }
            }
            diag[m] << "query t=" << std::setprecision(17) << f.timestamp << std::setprecision(6) << " (frame "
                    << f.index << ")" << (row.has_gt && row.report.localized
                                              ? ", error " + std::to_string(row.err_m) + " m"
                                              : std::string())
                    << ": " << reloc::describe(row.report, db) << "\n";
            std::cout << "t " << std::fixed << std::setprecision(3) << f.timestamp << " " << reloc::toString(modes[m])
                      << ": " << (row.report.localized ? "localized" : "not localized") << ", inliers "
                      << row.report.inliers << (row.report.localized && row.has_gt
                                                    ? ", error " + std::to_string(row.err_m) + " m"
                                                    : std::string())
                      << ", " << row.report.ms.total << " ms" << std::endl;
            rows[m].push_back(std::move(row));
        }
    }
    core::require(count > 0, o.input_rawlog, "no query frame (check every_n, and ground truth for query_image = quasi)");

    const std::string image =
        o.query_image == QueryImage::Camera ? "camera image" : "quasi-image at the ground-truth pose";
    const std::string what = "database " + o.database + " (" + db.summary() + "); queries: every " +
                             std::to_string(o.every_n) + "th left " + image + " of " + o.input_rawlog;
    core::StagedOutputs out;
    core::writeTextFileAtomically(out.addFile(o.output_dir + "/queries.txt"), query_times.str());
    std::vector<ModeSummary> summaries;
    for (size_t m = 0; m < modes.size(); ++m)
    {
        const std::string mode = reloc::toString(modes[m]);
        core::Trajectory traj;
        traj.header = "quasiloc-localize " + mode + ": T_world_cam0 of the localized queries";
        for (const auto& r : rows[m])
            if (r.report.localized) traj.poses.push_back({r.t, core::fromIsometry(r.report.T_world_cam)});
        core::writeTum(out.addFile(o.output_dir + "/" + mode + ".tum"), traj);
        core::writeTextFileAtomically(out.addFile(o.output_dir + "/" + mode + ".csv"), csvOf(rows[m]));
        core::writeTextFileAtomically(out.addFile(o.output_dir + "/" + mode + "_diagnostics.txt"), diag[m].str());
        summaries.push_back(summarize(mode, rows[m]));
    }
    const std::string md = markdownOf(summaries, what);
    core::writeTextFileAtomically(out.addFile(o.output_dir + "/summary.md"), md);
    core::writeTextFileAtomically(out.addFile(o.output_dir + "/summary.json"), jsonOf(summaries, what));
    core::writeEffectiveConfig(out.addFile(o.output_dir + "/quasiloc-localize.ini"),
                               {{"Localize", &o}, {"Localization", &lo}, {"PointMatching", &lo.matching}, {"QuasiImage", &qo}},
                               "quasiloc-localize effective configuration");
    out.commit();
    std::cout << "\n" << md << "outputs in " << o.output_dir << std::endl;
    return 0;
}
}  // namespace

int main(int argc, char** argv) { return core::runProgram(argc, argv, kUsage, run); }
