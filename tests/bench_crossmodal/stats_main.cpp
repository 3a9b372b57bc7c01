// bench_crossmodal_stats: what a camera image and the LiDAR map's quasi-image share, at the true pose, on the real
// KITTI raw sequence (../shared/data/kitti_raw_seq78) and on simulated sequences (one per [World] materials set):
// grey level against reflectivity per surface class, gradient orientation and magnitude, camera edges against depth
// and reflectivity discontinuities (modality_stats.h). Prints per-frame medians and inter-quartile ranges, real and
// simulated side by side.
#include <cctype>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <sstream>

#include "labelled_sequences.h"
#include "modality_stats.h"
#include "rank_stats.h"

namespace
{
using namespace quasiloc;
using namespace quasiloc::bench;

/** [BenchCrossModalStats] */
struct StatsOptions : public core::DeclaredOptions
{
    std::string kitti_dir = std::string(QUASILOC_SHARED_DIR) + "/data/kitti_raw_seq78";
    std::vector<std::string> kitti_maps = {"given"};
    int kitti_frames = 0;
    double kitti_max_depth_m = 60;
    std::string sim_world = "share/quasiloc/sim/V1_01_easy.ini";
    std::string sim_dir = "/tmp/quasiloc_bench_crossmodal_stats/V1_01_easy";
    std::vector<std::string> sim_materials = {"procedural", "spectral"};
    int sim_frames = 39;
    double sim_start_offset_s = 10;
    double sim_duration_s = 20;
    int cell_px = 4;
    double blur_sigma_px = 1.0;
    double depth_jump = 0.15;
    double edge_radius_px = 2.0;
    std::string overlay_dir;
    int overlay_frames = 3;
    bool per_frame = false;

    void declare(core::OptionTable& t) override
    {
        const core::Range any = core::Range::any(), pos = core::Range::above(0);
        t.add("kitti_dir", kitti_dir, "kitti_raw_seq78 folder");
        t.add("kitti_maps", kitti_maps,
              "KITTI maps, one column each: given (kitti_dir's map_even_frames_5cm.ply) or a .map / cloud file");
        t.add("kitti_frames", kitti_frames, "", any, "KITTI query frames, evenly spread (0: all 39; < 0: none)");
        t.add("kitti_max_depth_m", kitti_max_depth_m, "m", pos, "depth limit of projections and quasi-images on KITTI");
        t.add("sim_world", sim_world, "simulation INI");
        t.add("sim_dir", sim_dir, "simulated sequences: this prefix + _<materials> (simulated when missing)");
        t.add("sim_materials", sim_materials, "[World] materials sets to simulate, one column each (empty: none)");
        t.add("sim_frames", sim_frames, "", pos, "simulated frames, evenly spread over the simulated span");
        t.add("sim_start_offset_s", sim_start_offset_s, "s", any, "simulated span: start after the trajectory's");
        t.add("sim_duration_s", sim_duration_s, "s", pos, "simulated span: length");
        t.add("cell_px", cell_px, "px", pos, "z-buffer cell of the grey/reflectivity pairs");
        t.add("blur_sigma_px", blur_sigma_px, "px", pos, "Gaussian smoothing before the gradients");
        t.add("depth_jump", depth_jump, "", pos, "depth discontinuity: neighbours' log depths differ by more");
        t.add("edge_radius_px", edge_radius_px, "px", pos, "a camera edge this close to a discontinuity is near it");
        t.add("overlay_dir", overlay_dir,
              "if set: class and edge overlays (PNG) and grey/reflectivity pairs (CSV) of overlay_frames frames per "
              "sequence");
        t.add("overlay_frames", overlay_frames, "", pos, "overlays per sequence (evenly spread)");
        t.add("per_frame", per_frame, "also print every frame's figures");
    }
};

struct SequenceResult
{
    std::string column;
    std::vector<FrameModalityStats> frames;
    double wall_ms = 0, cpu_ms = 0;  ///< per frame
    std::array<size_t, kClasses> map_points{};
};

template <class F>
Summary over(const SequenceResult& r, F f)
{
    std::vector<double> v;
    for (const auto& s : r.frames) v.push_back(f(s));
    return summarise(v);
}

SequenceResult measure(const LabelledSequence& l, const quasi::QuasiOptions& qo, const ModalityOptions& mo,
                       const StatsOptions& b)
{
    SequenceResult r;
    r.column = l.column;
    for (uint8_t c : l.labels) ++r.map_points[std::min<int>(c, kClasses - 1)];
    quasi::QuasiRenderer renderer(l.seq.map, qo);
    if (!b.overlay_dir.empty())
    {
        std::filesystem::create_directories(b.overlay_dir);
        const size_t n = l.seq.frames.size(), k = std::min<size_t>(n, size_t(b.overlay_frames));
        for (size_t i = 0; i < k; ++i)
        {
            const QueryFrame& f = l.seq.frames[i * n / k];
            std::string name = l.column + "_" + f.name;
            for (char& ch : name)
                if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
            const std::string path = b.overlay_dir + "/classes_" + name + ".png";
            writeClassOverlay(path, f, l.seq.camera, l.seq.map, l.labels, renderer, mo);
            writePairsCsv(b.overlay_dir + "/pairs_" + name + ".csv", f, l.seq.camera, l.seq.map, l.labels, mo);
            std::cout << "overlay and pairs written to " << path << ", pairs_" << name << ".csv" << std::endl;
        }
    }
    const auto wall0 = std::chrono::steady_clock::now();
    const std::clock_t cpu0 = std::clock();
    for (size_t i = 0; i < l.seq.frames.size(); ++i)
    {
        r.frames.push_back(
            measureFrame(l.seq.frames[i], l.seq.camera, l.seq.map, l.labels, renderer, mo, uint32_t(1000 + i)));
        std::cout << "." << std::flush;
    }
    const double n = std::max<double>(1, double(l.seq.frames.size()));
    r.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall0).count() / n;
    r.cpu_ms = 1000.0 * double(std::clock() - cpu0) / CLOCKS_PER_SEC / n;
    std::cout << "\n";
    return r;
}

void header(const std::vector<SequenceResult>& rs, const std::string& first)
{
    std::cout << "| " << first << " |";
    for (const auto& r : rs) std::cout << " " << r.column << " |";
    std::cout << "\n|---|";
    for (size_t i = 0; i < rs.size(); ++i) std::cout << "---|";
    std::cout << "\n";
}

template <class F>
void row(const std::vector<SequenceResult>& rs, const std::string& name, F f, int precision = 3)
{
    std::cout << "| " << name << " |";
    for (const auto& r : rs) std::cout << " " << formatSummary(over(r, f), precision) << " |";
    std::cout << "\n";
}

void printTables(const std::vector<SequenceResult>& rs, const ModalityOptions& mo)
{
    std::cout << "\n## Frames, surface classes and time\n\n";
    header(rs, "");
    std::cout << "| frames |";
    for (const auto& r : rs) std::cout << " " << r.frames.size() << " |";
    std::cout << "\n| time per frame: wall / CPU [ms] |";
    for (const auto& r : rs)
        std::cout << " " << std::fixed << std::setprecision(0) << r.wall_ms << " / " << r.cpu_ms << " |";
    std::cout << "\n";
    for (int k = 0; k < kClasses; ++k)
    {
        std::cout << "| map points: " << sim::toString(sim::SurfaceClass(k)) << " |";
        for (const auto& r : rs)
        {
            size_t total = 0;
            for (size_t c : r.map_points) total += c;
            std::cout << " " << std::setprecision(1)
                      << 100.0 * double(r.map_points[k]) / double(std::max<size_t>(1, total)) << " % |";
        }
        std::cout << "\n";
    }

    std::cout << "\n## Grey level against reflectivity: Spearman per frame, median [IQR] (pairs: nearest map point per "
              << mo.cell_px << " x " << mo.cell_px << " px cell; a class needs " << mo.min_points
              << " pairs in a frame)\n\n";
    header(rs, "class");
    row(rs, "all", [](const FrameModalityStats& s) { return s.grey_refl_all; });
    row(rs, "lower half of the image", [](const FrameModalityStats& s) { return s.grey_refl_lower; });
    row(rs, "upper half of the image", [](const FrameModalityStats& s) { return s.grey_refl_upper; });
    for (int k = 0; k < kClasses; ++k)
        row(rs, sim::toString(sim::SurfaceClass(k)), [k](const FrameModalityStats& s) { return s.grey_refl_class[k]; });
    row(
        rs, "pairs per frame: all", [](const FrameModalityStats& s) { return double(s.points_all); }, 0);
    for (int k = 0; k < kClasses; ++k)
        row(
            rs, std::string("pairs per frame: ") + sim::toString(sim::SurfaceClass(k)),
            [k](const FrameModalityStats& s) { return double(s.points_class[k]); }, 0);

    std::cout << "\n## Structure: camera image against the quasi-image's channels, median [IQR] over frames\n\n";
    header(rs, "measure");
    row(rs, "pixels compared (share of the image)", [](const FrameModalityStats& s) { return s.valid_fraction; });
    row(rs, "orientation agreement, reflectivity", [](const FrameModalityStats& s) { return s.orient_refl; });
    row(rs, "  chance (shuffled pixels)", [](const FrameModalityStats& s) { return s.orient_refl_chance; });
    row(rs, "orientation agreement, depth", [](const FrameModalityStats& s) { return s.orient_depth; });
    row(rs, "  chance (shuffled pixels)", [](const FrameModalityStats& s) { return s.orient_depth_chance; });
    row(rs, "gradient magnitude Spearman, reflectivity", [](const FrameModalityStats& s) { return s.magnitude_refl; });
    row(rs, "  baseline (camera shifted)", [](const FrameModalityStats& s) { return s.magnitude_refl_shifted; });
    row(rs, "gradient magnitude Spearman, depth", [](const FrameModalityStats& s) { return s.magnitude_depth; });
    row(rs, "  baseline (camera shifted)", [](const FrameModalityStats& s) { return s.magnitude_depth_shifted; });
    row(
        rs, "camera edges per frame", [](const FrameModalityStats& s) { return double(s.camera_edges); }, 0);
    row(rs, "camera edges near a depth discontinuity", [](const FrameModalityStats& s) { return s.edges_depth; });
    row(rs, "  baseline (camera shifted)", [](const FrameModalityStats& s) { return s.edges_depth_shifted; });
    row(rs, "  pixels near one (density)", [](const FrameModalityStats& s) { return s.depth_density; });
    row(rs, "camera edges near a reflectivity edge", [](const FrameModalityStats& s) { return s.edges_refl; });
    row(rs, "  baseline (camera shifted)", [](const FrameModalityStats& s) { return s.edges_refl_shifted; });
    row(rs, "  pixels near one (density)", [](const FrameModalityStats& s) { return s.refl_density; });
    std::cout << std::flush;
}

void printPerFrame(const SequenceResult& r)
{
    std::cout << "\n### " << r.column
              << ": per frame\n\n| frame | all | road | marking | facade | vegetation | vehicle | "
                 "orient refl / chance | orient depth / chance | edges near depth / shifted | edges near refl / "
                 "shifted |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
    std::cout << std::fixed << std::setprecision(3);
    for (size_t i = 0; i < r.frames.size(); ++i)
    {
        const auto& s = r.frames[i];
        std::cout << "| " << i << " | " << s.grey_refl_all;
        for (int k = 0; k < 5; ++k) std::cout << " | " << s.grey_refl_class[k];
        std::cout << " | " << s.orient_refl << " / " << s.orient_refl_chance << " | " << s.orient_depth << " / "
                  << s.orient_depth_chance << " | " << s.edges_depth << " / " << s.edges_depth_shifted << " | "
                  << s.edges_refl << " / " << s.edges_refl_shifted << " |\n";
    }
}

const char* kUsage =
    "Usage: bench_crossmodal_stats [config.ini] [--set Section.key=value]...\n"
    "What camera images and the LiDAR map share at the true pose, on kitti_raw_seq78 and on simulated sequences\n"
    "(one per [World] materials set): grey level against reflectivity per surface class, gradient orientation and\n"
    "magnitude, camera edges against depth and reflectivity discontinuities. Prints median [IQR] over frames.\n"
    "Sections: [BenchCrossModalStats], [GeometricClasses], [QuasiImage]. Run from the repository root.";

int run(const core::CommandLine& cmd_in)
{
    const core::CommandLine cmd = core::withOptionalConfig(cmd_in);
    const mrpt::config::CConfigFileMemory cfg = core::loadConfig(cmd);
    const std::string name = cmd.config_path.empty() ? "command line" : cmd.config_path;
    StatsOptions b;
    core::loadOptionsChecked(b, cfg, "BenchCrossModalStats", name);
    GeometricClassOptions go;
    core::loadOptionsChecked(go, cfg, "GeometricClasses", name);
    quasi::QuasiOptions qo;
    core::loadOptionsChecked(qo, cfg, "QuasiImage", name);
    qo.check(name);
    ModalityOptions mo;
    mo.cell_px = b.cell_px, mo.blur_sigma_px = b.blur_sigma_px, mo.depth_jump = b.depth_jump;
    mo.edge_radius_px = b.edge_radius_px;

    std::cout << "# bench_crossmodal_stats\n" << std::flush;
    std::vector<SequenceResult> results;
    for (const std::string& kitti_map : b.kitti_frames >= 0 ? b.kitti_maps : std::vector<std::string>{})
    {
        GeometricClassStats gs;
        LabelledSequence k =
            loadLabelledKitti(b.kitti_dir, b.kitti_frames, kitti_map == "given" ? "" : kitti_map, go, &gs);
        k.column =
            "KITTI " +
            (kitti_map == "given" ? std::string("given map") : std::filesystem::path(kitti_map).stem().string()) +
            " (real)";
        std::cout << k.column << ": map classified in " << std::fixed << std::setprecision(1) << gs.seconds
                  << " s, road region " << std::setprecision(0) << gs.road_region_m2 << " m2\n";
        quasi::QuasiOptions kq = qo;
        kq.max_depth_m = b.kitti_max_depth_m;
        ModalityOptions km = mo;
        km.max_depth_m = b.kitti_max_depth_m;
        results.push_back(measure(k, kq, km, b));
    }
    for (const std::string& materials : b.sim_materials)
    {
        const LabelledSequence s =
            loadLabelledSim(b.sim_dir, b.sim_world, materials, b.sim_start_offset_s, b.sim_duration_s, b.sim_frames);
        ModalityOptions sm = mo;
        sm.max_depth_m = qo.max_depth_m;
        results.push_back(measure(s, qo, sm, b));
    }
    core::require(!results.empty(), name, "nothing to measure: kitti_frames < 0 and no sim_materials");
    printTables(results, mo);
    if (b.per_frame)
        for (const auto& r : results) printPerFrame(r);
    return 0;
}
}  // namespace

int main(int argc, char** argv) { return core::runProgram(argc, argv, kUsage, run, false); }
