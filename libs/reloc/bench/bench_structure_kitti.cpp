// bench_structure_kitti: single-image global localization by structure (reloc/structure_localizer.h) of the real KITTI
// raw query frames (../shared/data/kitti_raw_seq78) against views rendered from a LiDAR map (the carved map of
// map-build, or the given fused one), sampled over the map's drivable free space by view_sampling.h as
// quasiloc-build-db samples a database's views. Prints per frame the answer, its error and the retrieval ranks, then
// Recall@0.1/0.3/1.0 m and mATE (docs/crossmodal_matching.md, "Part 4").
//
//     bench_structure_kitti [config.ini] [--set Section.key=value]...
//
// Sections: [BenchStructureKitti] (below), [ViewSampling], [StructureLocalization], [QuasiImage].
#include <chrono>
#include <ctime>
#include <iomanip>
#include <iostream>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/reloc/structure_localizer.h>
#include <quasiloc/reloc/view_sampling.h>

#include "kitti_sequence.h"

namespace
{
using namespace quasiloc;

/** [BenchStructureKitti] */
struct BenchOptions : public core::DeclaredOptions
{
    std::string kitti_dir = std::string(QUASILOC_SHARED_DIR) + "/data/kitti_raw_seq78";
    std::string map;  ///< empty: the folder's fused map
    int frames = 10;
    double region_margin_m = 4;

    void declare(core::OptionTable& t) override
    {
        t.add("kitti_dir", kitti_dir, "kitti_raw_seq78 folder");
        t.add("map", map, "the LiDAR map: a .map (map-build, map-import) or a cloud; empty: kitti_dir's fused map");
        t.add("frames", frames, "", core::Range::atLeast(0), "query frames, evenly spread (0: all 39)");
        t.add("region_margin_m", region_margin_m, "m", core::Range::atLeast(0),
              "views are sampled over the query positions' bounding box grown by this (the drive's corridor)");
    }
};

/** KITTI's views: the camera 1.65 m above the ground, level, 16 headings, a 1 m grid, no enclosure (outdoors). */
reloc::ViewSamplingOptions kittiSampling()
{
    reloc::ViewSamplingOptions s;
    s.grid_spacing_m = 1.0;
    s.heights_m = {1.65};
    s.num_headings = 16;
    s.pitches_deg = {0};
    s.require_enclosed = false;
    s.clearance_m = 0.5;
    return s;
}

const char* kUsage =
    "Usage: bench_structure_kitti [config.ini] [--set Section.key=value]...\n"
    "Single-image global localization by structure of the KITTI raw query frames against views rendered from a\n"
    "LiDAR map. Sections: [BenchStructureKitti], [ViewSampling], [StructureLocalization], [QuasiImage].";

int run(const core::CommandLine& cmd_in)
{
    const core::CommandLine cmd = core::withOptionalConfig(cmd_in);
    const mrpt::config::CConfigFileMemory cfg = core::loadConfig(cmd);
    const std::string name = cmd.config_path.empty() ? "command line" : cmd.config_path;
    BenchOptions b;
    core::loadOptionsChecked(b, cfg, "BenchStructureKitti", name);
    reloc::ViewSamplingOptions sampling = kittiSampling();
    core::loadOptionsChecked(sampling, cfg, "ViewSampling", name);
    reloc::StructureLocalizerOptions so;
    core::loadOptionsChecked(so, cfg, "StructureLocalization", name);
    quasi::QuasiOptions qo;
    qo.max_depth_m = 60;
    qo.reflectivity_scope = "map";
    core::loadOptionsChecked(qo, cfg, "QuasiImage", name);
    qo.check(name);

    const bench::CrossModalSequence seq = bench::loadKittiSequence(b.kitti_dir, b.frames, b.map);
    if (sampling.region.empty())
    {
        Eigen::Vector2d lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
        for (const auto& f : seq.frames)
            lo = lo.cwiseMin(f.T_world_cam.translation().head<2>()),
            hi = hi.cwiseMax(f.T_world_cam.translation().head<2>());
        sampling.region = {lo.x() - b.region_margin_m, lo.y() - b.region_margin_m, hi.x() + b.region_margin_m,
                           hi.y() + b.region_margin_m};
    }
    sampling.check(name);
    reloc::ViewSamplingStats stats;
    const std::vector<mrpt::poses::CPose3D> views = reloc::sampleViewpoints(seq.map, sampling, &stats);
    std::cout << "# bench_structure_kitti (real)\nmap " << (b.map.empty() ? "given" : b.map) << ": " << seq.map.size()
              << " points; " << views.size() << " views (" << stats.positions << " positions x "
              << sampling.num_headings << " headings) over x " << sampling.region[0] << ".." << sampling.region[2]
              << ", y " << sampling.region[1] << ".." << sampling.region[3] << " m" << std::endl;
    reloc::StructureLocalizer localizer(seq.map, views, seq.camera, qo, so);
    std::cout << localizer.summary() << std::endl;

    int n = 0, r01 = 0, r03 = 0, r1 = 0, wrong = 0;
    double sum_err = 0, sum_ms = 0, sum_cpu_ms = 0;
    for (const auto& f : seq.frames)
    {
        const std::clock_t c0 = std::clock();
        const reloc::LocalizationReport r = localizer.localize(f.image, &f.T_world_cam);
        sum_cpu_ms += 1e3 * double(std::clock() - c0) / CLOCKS_PER_SEC;
        sum_ms += r.ms.total;
        ++n;
        const double e = r.localized ? core::translationDistance(r.T_world_cam, f.T_world_cam) : INFINITY;
        r01 += e <= 0.1, r03 += e <= 0.3, r1 += e <= 1.0, wrong += r.localized && e > 1.0;
        if (e <= 1.0) sum_err += e;
        std::cout << f.name << ": " << localizer.describeLast() << std::endl;
    }
    std::cout << std::fixed << std::setprecision(1) << "\n| queries (real) | localized | Recall@0.1 m | Recall@0.3 m | "
              << "Recall@1.0 m | mATE (<= 1 m) [cm] | wrong (> 1 m) | ms/query wall | CPU "
                 "|\n|---|---|---|---|---|---|---|---|---|\n| "
              << n << " | " << (r1 + wrong) << " | " << 100.0 * r01 / n << " % | " << 100.0 * r03 / n << " % | "
              << 100.0 * r1 / n << " % | " << (r1 ? 100 * sum_err / r1 : NAN) << " | " << wrong << " | " << sum_ms / n
              << " | " << sum_cpu_ms / n << " |" << std::endl;
    return 0;
}
}  // namespace

int main(int argc, char** argv) { return core::runProgram(argc, argv, kUsage, run, false); }
