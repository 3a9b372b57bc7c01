#include "build_modes.h"

#include <mrpt/system/CTimeLogger.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <quasiloc/core/error.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/dataset/calibration.h>
#include <sstream>

namespace quasiloc::app
{
namespace
{
using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/** Prints "views a/b (p %)" about every 10 %. */
reloc::BuildProgress consoleProgress()
{
    auto last_percent = std::make_shared<int>(-1);
    return [last_percent](size_t done, size_t total) {
        const int percent = int(100 * done / total);
        if (percent / 10 != *last_percent / 10 || done == total)
            std::cout << "views " << done << "/" << total << " (" << percent << " %)" << std::endl;
        *last_percent = percent;
    };
}

map::LidarMap loadMap(const BuildInputs& in)
{
    const map::LidarMap map = map::LidarMap::load(in.run.map_file);
    std::cout << "map " << map.summary() << "\ncamera " << in.camera.width << "x" << in.camera.height << " fx "
              << in.camera.fx << std::endl;
    return map;
}

/** The database, <output>.views.tum and <output>.ini, all or nothing; the database records the map's absolute
 *  path (a whole build and a merge given the same map_file record the same). */
void writeDatabaseOutputs(const BuildInputs& in, reloc::Database& db)
{
    db.map_file = std::filesystem::absolute(in.run.map_file).string();
    core::StagedOutputs out;
    db.save(out.addFile(in.run.output));
    core::Trajectory views;
    views.header = "quasiloc-build-db views: T_world_cam of every database view (time = view id)";
    for (const auto& v : db.views) views.poses.push_back({double(v.id), v.T_world_cam});
    core::writeTum(out.addFile(in.run.output + ".views.tum"), views);
    core::writeEffectiveConfig(out.addFile(in.run.output + ".ini"), in.sections(),
                               "quasiloc-build-db effective configuration");
    out.commit();
}

void printSampling(const reloc::ViewSamplingStats& s)
{
    std::cout << "grid        " << s.grid_positions << " cells: " << s.no_floor << " without floor, " << s.not_clear
              << " (cell, height) too close to geometry, " << s.not_enclosed << " not enclosed, " << s.positions
              << " positions kept\n";
}

void printViews(const reloc::DatabaseBuildStats& st, const BuildRunOptions& o)
{
    std::ostringstream line;  // the thresholds as written in the INI file, whatever the console's format
    line << "views       " << st.rendered << " rendered, " << st.dropped_valid << " dropped (valid pixels < "
         << o.min_valid_fraction << "), " << st.dropped_lifted << " dropped (lifted keypoints < " << o.min_lifted
         << "), " << st.kept << " kept\n";
    std::cout << line.str();
}

std::string viewsTime(const reloc::DatabaseBuildStats& st)
{
    std::ostringstream s;
    s << std::fixed << std::setprecision(1) << "views " << st.ms_views / 1000 << " s (" << st.threads << " workers, "
      << std::setprecision(2) << st.ms_per_view_cpu << " ms per view each)";
    return s.str();
}

/** ", x [a, b] y [c, d] m" over the shard's kept views; empty when it kept none. */
std::string tileExtent(const reloc::DatabaseShard& s)
{
    if (s.views.empty()) return "";
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (const auto& v : s.views)
    {
        x0 = std::min(x0, v.T_world_cam.x());
        x1 = std::max(x1, v.T_world_cam.x());
        y0 = std::min(y0, v.T_world_cam.y());
        y1 = std::max(y1, v.T_world_cam.y());
    }
    std::ostringstream text;
    text << std::fixed << std::setprecision(1) << ": x [" << x0 << ", " << x1 << "] y [" << y0 << ", " << y1 << "] m";
    return text.str();
}

void printStageTimes(const char* program, const std::vector<std::pair<const char*, double>>& stages_ms)
{
    mrpt::system::CTimeLogger timer(true, program);
    for (const auto& [stage, ms] : stages_ms) timer.registerUserMeasure(stage, ms * 1e-3, true);
    std::cout << timer.getStatsAsText();
    timer.clear(true);
}
}  // namespace

std::vector<core::OptionsSection> BuildInputs::sections() const
{
    auto s = frontend.sections();
    s.insert(s.end(), {{"BuildDatabase", &run},
                       {"ViewSampling", &config.sampling},
                       {"QuasiImage", &config.quasi},
                       {"Vocabulary", &config.vocabulary}});
    return s;
}

BuildInputs loadBuildInputs(const core::CommandLine& cmd)
{
    BuildInputs in;
    const auto cfg = core::loadConfig(cmd);
    const std::string& name = in.config_name = cmd.config_path;
    in.print_timing = cmd.print_timing;
    BuildRunOptions& o = in.run;
    core::loadOptionsChecked(o, cfg, "BuildDatabase", name);
    core::requireInputFiles(name, "BuildDatabase", {{"map_file", o.map_file}, {"calibration_ini", o.calibration_ini}});
    core::require(!o.output.empty(), name + ": [BuildDatabase] output", "is required");
    reloc::DatabaseBuildConfig& bc = in.config;
    bc.build = o;
    core::loadOptionsChecked(bc.sampling, cfg, "ViewSampling", name);
    bc.sampling.check(name);
    core::loadOptionsChecked(bc.quasi, cfg, "QuasiImage", name);
    bc.quasi.check(name);
    core::loadOptionsChecked(bc.vocabulary, cfg, "Vocabulary", name);
    bc.vocabulary.check(name);
    in.frontend.load(cfg, name);
    bc.features = in.frontend.features;
    bc.lines = in.frontend.lines;
    bc.association = in.frontend.association;
    in.camera = dataset::loadCalibration(o.calibration_ini).rig.left;
    return in;
}

int buildWhole(const BuildInputs& in)
{
    const auto t0 = Clock::now();
    const map::LidarMap map = loadMap(in);
    reloc::DatabaseBuildStats st;
    reloc::Database db = reloc::buildDatabase(map, in.camera, in.config, &st, consoleProgress());
    writeDatabaseOutputs(in, db);

    printSampling(st.sampling);
    printViews(st, in.run);
    std::cout << std::fixed << std::setprecision(1) << "database    " << db.summary() << "\n"
              << "time        sampling " << st.ms_sampling / 1000 << " s, " << viewsTime(st) << ", vocabulary "
              << st.ms_vocabulary / 1000 << " s, index " << st.ms_index / 1000 << " s, total " << secondsSince(t0)
              << " s\n"
              << "outputs     " << in.run.output << " {,.views.tum,.ini}" << std::endl;
    if (in.print_timing)
        printStageTimes("quasiloc-build-db", {{"sampling", st.ms_sampling},
                                              {"views", st.ms_views},
                                              {"vocabulary", st.ms_vocabulary},
                                              {"index", st.ms_index}});
    return 0;
}

int buildShard(const BuildInputs& in, reloc::ShardSelection shard)
{
    const auto t0 = Clock::now();
    const map::LidarMap map = loadMap(in);
    const double s_load = secondsSince(t0);
    reloc::DatabaseBuildStats st;
    reloc::DatabaseShard s = reloc::buildDatabaseShard(map, in.camera, in.config, shard, &st, consoleProgress());
    auto t = Clock::now();
    s.map = reloc::MapIdentity::ofFile(in.run.map_file);
    s.map_file = std::filesystem::absolute(in.run.map_file).string();
    const double s_identify = secondsSince(t);
    s.build_seconds = secondsSince(t0);
    const std::string path = reloc::shardPath(in.run.output, shard);
    t = Clock::now();
    s.save(path);
    const double s_write = secondsSince(t);

    printSampling(st.sampling);
    std::cout << "shard       " << shard.text() << ": " << st.rendered << " of " << st.sampled
              << " sampled views (its tile" << tileExtent(s) << ")\n";
    printViews(st, in.run);
    std::cout << std::fixed << std::setprecision(1) << "time        map " << s_load << " s, sampling "
              << st.ms_sampling / 1000 << " s, " << viewsTime(st) << ", map identity " << s_identify << " s, write "
              << s_write << " s, total " << secondsSince(t0) << " s\n"
              << "output      " << path << "\n"
              << std::setprecision(2) << "shard " << shard.text() << ": " << st.rendered << " views, " << st.kept
              << " kept, " << secondsSince(t0) << " s" << std::endl;
    if (in.print_timing)
        printStageTimes("quasiloc-build-db --shard", {{"map", s_load * 1000},
                                                      {"sampling", st.ms_sampling},
                                                      {"views", st.ms_views},
                                                      {"map identity", s_identify * 1000},
                                                      {"write", s_write * 1000}});
    return 0;
}

int mergeShards(const BuildInputs& in, int count)
{
    const auto t0 = Clock::now();
    reloc::ShardExpectation expect;
    expect.count = count;
    expect.map = reloc::MapIdentity::ofFile(in.run.map_file);
    expect.map_file = in.run.map_file;
    expect.options = reloc::resultOptionsText(in.config, in.camera);
    expect.config_name = in.config_name;
    std::vector<reloc::DatabaseShard> shards = reloc::loadShardsForMerge(in.run.output, expect);
    const double s_load = secondsSince(t0);
    std::cout << std::fixed;
    for (const auto& s : shards)
        std::cout << "shard " << std::setw(9) << std::left << s.selection.text() << std::right << std::setw(7)
                  << s.rendered << " views, " << std::setw(7) << s.views.size() << " kept, built in "
                  << std::setprecision(2) << s.build_seconds << " s" << std::endl;

    reloc::DatabaseBuildStats st;
    reloc::Database db = reloc::finishDatabase(std::move(shards), in.config.vocabulary, &st);
    const auto t = Clock::now();
    writeDatabaseOutputs(in, db);
    const double s_write = secondsSince(t);

    printViews(st, in.run);
    std::cout << std::setprecision(1) << "database    " << db.summary() << "\n"
              << "time        check + load " << count << " shards " << s_load << " s, vocabulary "
              << st.ms_vocabulary / 1000 << " s, index " << st.ms_index / 1000 << " s, write " << s_write
              << " s, total " << secondsSince(t0) << " s\n"
              << "outputs     " << in.run.output << " {,.views.tum,.ini}\n"
              << std::setprecision(2) << "merge of " << count << " shards: " << st.kept << " views, "
              << secondsSince(t0) << " s" << std::endl;
    if (in.print_timing)
        printStageTimes("quasiloc-build-db --merge", {{"load", s_load * 1000},
                                                      {"vocabulary", st.ms_vocabulary},
                                                      {"index", st.ms_index},
                                                      {"write", s_write * 1000}});
    return 0;
}

}  // namespace quasiloc::app
