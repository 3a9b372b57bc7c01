// quasiloc-build-db: renders a database of virtual views from a LiDAR map alone (libs/reloc/database_builder.h)
// for global localization (quasiloc-localize, the tracker's initialisation and relocalization).
//
//     quasiloc-build-db <config.ini> [--set Section.key=value]... [--print-timing]
//
// [BuildDatabase]: BuildRunOptions::declare below (the file keys) and the library's keys (database_builder.h).
// Other sections: [ViewSampling] [QuasiImage] [Features] [Lines] [Association] [Vocabulary].
//
// Outputs, all or nothing: the database, <output>.views.tum (T_world_cam of every kept view, time = view id, for
// SceneViewer3D / plotting) and <output>.ini (the effective configuration). Progress goes to the console.
#include <mrpt/system/CTimeLogger.h>

#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <quasiloc/dataset/calibration.h>
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/frontend/frontend.h>
#include <quasiloc/reloc/database_builder.h>

#include "build_options.h"

namespace
{
using namespace quasiloc;
using app::BuildRunOptions;


const char* kUsage =
    "usage: quasiloc-build-db <config.ini> [--set Section.key=value]... [--print-timing]\n"
    "Renders virtual views of a LiDAR map and writes the global-localization database ([BuildDatabase] output).";

int run(const core::CommandLine& cmd)
{
    const auto cfg = core::loadConfig(cmd);
    const std::string name = cmd.config_path;
    BuildRunOptions o;
    core::loadOptionsChecked(o, cfg, "BuildDatabase", name);
    core::requireInputFiles(name, "BuildDatabase", {{"map_file", o.map_file}, {"calibration_ini", o.calibration_ini}});
    core::require(!o.output.empty(), name + ": [BuildDatabase] output", "is required");
    reloc::DatabaseBuildConfig bc;
    bc.build = o;
    core::loadOptionsChecked(bc.sampling, cfg, "ViewSampling", name);
    bc.sampling.check(name);
    core::loadOptionsChecked(bc.quasi, cfg, "QuasiImage", name);
    bc.quasi.check(name);
    core::loadOptionsChecked(bc.vocabulary, cfg, "Vocabulary", name);
    bc.vocabulary.check(name);
    frontend::FrontendOptions fo;
    fo.load(cfg, name);
    bc.features = fo.features;
    bc.lines = fo.lines;
    bc.association = fo.association;

    const auto t0 = std::chrono::steady_clock::now();
    const map::LidarMap map = map::LidarMap::load(o.map_file);
    const core::CameraModel camera = dataset::loadCalibration(o.calibration_ini).rig.left;
    std::cout << "map " << map.summary() << "\ncamera " << camera.width << "x" << camera.height << " fx "
              << camera.fx << std::endl;

    int last_percent = -1;
    reloc::DatabaseBuildStats st;
    reloc::Database db = reloc::buildDatabase(map, camera, bc, &st, [&](size_t done, size_t total) {
        const int percent = int(100 * done / total);
        if (percent / 10 != last_percent / 10 || done == total)
            std::cout << "views " << done << "/" << total << " (" << percent << " %)" << std::endl;
        last_percent = percent;
    });
    db.map_file = std::filesystem::absolute(o.map_file).string();

    core::StagedOutputs out;
    db.save(out.addFile(o.output));
    core::Trajectory views;
    views.header = "quasiloc-build-db views: T_world_cam of every database view (time = view id)";
    for (const auto& v : db.views) views.poses.push_back({double(v.id), v.T_world_cam});
    core::writeTum(out.addFile(o.output + ".views.tum"), views);
    auto sections = fo.sections();
    sections.insert(sections.end(), {{"BuildDatabase", &o}, {"ViewSampling", &bc.sampling}, {"QuasiImage", &bc.quasi},
                                     {"Vocabulary", &bc.vocabulary}});
    core::writeEffectiveConfig(out.addFile(o.output + ".ini"), sections, "quasiloc-build-db effective configuration");
    out.commit();

    const double total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto& s = st.sampling;
    std::cout << std::fixed << std::setprecision(1) << "grid        " << s.grid_positions << " cells: " << s.no_floor
              << " without floor, " << s.not_clear << " (cell, height) too close to geometry, " << s.not_enclosed
              << " not enclosed, " << s.positions << " positions kept\n"
              << "views       " << st.rendered << " rendered, " << st.dropped_valid << " dropped (valid pixels < "
              << o.min_valid_fraction << "), " << st.dropped_lifted << " dropped (lifted keypoints < " << o.min_lifted
              << "), " << st.kept << " kept\n"
              << "database    " << db.summary() << "\n"
              << "time        sampling " << st.ms_sampling / 1000 << " s, views " << st.ms_views / 1000 << " s ("
              << st.threads << " workers, " << std::setprecision(2) << st.ms_per_view_cpu << " ms per view each), "
              << std::setprecision(1) << "vocabulary " << st.ms_vocabulary / 1000 << " s, index " << st.ms_index / 1000
              << " s, total " << total_s << " s\n"
              << "outputs     " << o.output << " {,.views.tum,.ini}" << std::endl;
    if (cmd.print_timing)
    {
        mrpt::system::CTimeLogger timer(true, "quasiloc-build-db");
        for (const auto& [stage, ms] : {std::pair<const char*, double>{"sampling", st.ms_sampling},
                                        {"views", st.ms_views},
                                        {"vocabulary", st.ms_vocabulary},
                                        {"index", st.ms_index}})
            timer.registerUserMeasure(stage, ms * 1e-3, true);
        std::cout << timer.getStatsAsText();
        timer.clear(true);
    }
    return 0;
}
}  // namespace

int main(int argc, char** argv) { return core::runProgram(argc, argv, kUsage, run); }
