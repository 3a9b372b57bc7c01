// bench_crossmodal_match: which cross-modal descriptor and map channel find the most correct correspondences between
// a camera image and the LiDAR map's quasi-image, at the true pose and from guesses 0.1 m / 1 deg and 0.3 m / 3 deg
// off, on the real KITTI raw sequence (../shared/data/kitti_raw_seq78; the given map and any map-build map) and on
// simulated sequences (one per [World] materials set). crossmodal_match.h says how matches are found and counted;
// docs/crossmodal_matching.md holds the tables.
#include <chrono>
#include <ctime>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
#include <random>
#include <sstream>

#include "crossmodal_match.h"
#include "labelled_sequences.h"
#include "rank_stats.h"

namespace
{
using namespace quasiloc;
using namespace quasiloc::bench;

/** [BenchCrossModalMatch] */
struct MatchMainOptions : public core::DeclaredOptions
{
    std::string kitti_dir = std::string(QUASILOC_SHARED_DIR) + "/data/kitti_raw_seq78";
    std::vector<std::string> kitti_maps = {"given"};
    int kitti_frames = 10;
    double kitti_max_depth_m = 60;
    std::string sim_world = "share/quasiloc/sim/V1_01_easy.ini";
    std::string sim_dir = "/tmp/quasiloc_bench_crossmodal_stats/V1_01_easy";
    std::vector<std::string> sim_materials = {"procedural", "spectral"};
    int sim_frames = 10;
    double sim_start_offset_s = 10;
    double sim_duration_s = 20;
    int draws = 3;
    int seed = 7;
    std::string xfeat_model = std::string(QUASILOC_SHARED_DIR) + "/models/xfeat/xfeat_dyn_op11.onnx";
    std::string lighterglue_model = std::string(QUASILOC_SHARED_DIR) + "/models/lighterglue/lighterglue_L3_ts.pt";
    int xfeat_keypoints = 512;
    MatchBenchOptions m;

    void declare(core::OptionTable& t) override
    {
        const core::Range any = core::Range::any(), pos = core::Range::above(0);
        t.add("kitti_dir", kitti_dir, "kitti_raw_seq78 folder");
        t.add("kitti_maps", kitti_maps,
              "KITTI maps, one column each: given (kitti_dir's map_even_frames_5cm.ply) or a .map / cloud file");
        t.add("kitti_frames", kitti_frames, "", any, "KITTI query frames, evenly spread (0: all 39; < 0: none)");
        t.add("kitti_max_depth_m", kitti_max_depth_m, "m", pos, "quasi-image depth limit on KITTI");
        t.add("sim_world", sim_world, "simulation INI");
        t.add("sim_dir", sim_dir, "simulated sequences: this prefix + _<materials> (simulated when missing)");
        t.add("sim_materials", sim_materials, "[World] materials sets to simulate, one column each (empty: none)");
        t.add("sim_frames", sim_frames, "", pos, "simulated frames, evenly spread over the simulated span");
        t.add("sim_start_offset_s", sim_start_offset_s, "s", any, "simulated span: start after the trajectory's");
        t.add("sim_duration_s", sim_duration_s, "s", pos, "simulated span: length");
        t.add("draws", draws, "", core::Range::between(1, 100), "random guesses per frame and offset level");
        t.add("seed", seed, "", any, "seed of the guesses");
        t.add("xfeat_model", xfeat_model, "XFeat ONNX model (missing: the XFeat rows say so)");
        t.add("lighterglue_model", lighterglue_model, "LighterGlue TorchScript model (missing: the row says so)");
        t.add("xfeat_keypoints", xfeat_keypoints, "", pos, "XFeat keypoints per image");
        t.add("keypoints", m.keypoints, "", pos, "map keypoints per guess (half reflectivity, half depth corners)");
        t.add("min_keypoint_distance_px", m.min_keypoint_distance_px, "px", pos, "between map keypoints");
        t.add("min_valid_share", m.min_valid_share, "", core::Range::between(0, 1),
              "a keypoint's descriptor footprint must be this valid in the quasi-image");
        t.add("window_base_px", m.window_base_px, "px", pos, "search radius at the true pose");
        t.add("window_max_px", m.window_max_px, "px", pos, "largest search radius");
        t.add("ratio", m.ratio, "", pos, "accept when best / second-best distance is below");
        t.add("correct_px", m.correct_px, "px", pos, "a match is correct this close to the true projection");
        t.add("depth_bands", m.depth_bands, "", core::Range::between(1, 64), "rank equalisation: log-depth bands");
        t.add("fill_sigma_px", m.fill_sigma_px, "px", pos, "quasi-image holes filled by normalised convolution");
        t.add("depth_edge_sigma_px", m.depth_edge_sigma_px, "px", pos, "depth edges: local mean of log depth");
        t.add("depth_edge_scale", m.depth_edge_scale, "", pos, "depth edges: tanh scale of the log-depth residual");
        t.add("local_norm_sigma_px", m.local_norm_sigma_px, "px", pos, "camera local normalisation window");
        t.add("local_norm_min_std", m.local_norm_min_std, "grey levels", pos, "camera local normalisation floor");
        t.add("smooth_sigma_px", m.descriptors.smooth_sigma_px, "px", any, "smoothing before every descriptor");
        t.add("ncc_radius_px", m.descriptors.ncc_radius_px, "px", pos, "NCC patch radius");
        t.add("mind_distance_px", m.descriptors.mind_distance_px, "px", pos, "MIND-SSC neighbour distance");
        t.add("mind_grid", m.descriptors.mind_grid, "", pos, "MIND-SSC read on this grid ...");
        t.add("mind_step_px", m.descriptors.mind_step_px, "px", pos, "... with this step");
        t.add("orientation_cell_px", m.descriptors.orientation_cell_px, "px", pos, "orientation field cell");
        t.add("orientation_cells", m.descriptors.orientation_cells, "", pos, "orientation field cells per side");
    }
};

struct Level
{
    const char* name;
    double t_m, rot_deg;
};
const Level kLevels[] = {{"true pose", 0, 0}, {"0.1 m / 1 deg off", 0.1, 1.0}, {"0.3 m / 3 deg off", 0.3, 3.0}};
constexpr int kLevelCount = 3;

/** The true pose moved in the camera frame by exactly t_m along and rot_deg about random directions. */
Eigen::Isometry3d perturb(const Eigen::Isometry3d& T_world_cam, const Level& l, std::mt19937& rng)
{
    std::normal_distribution<double> n;
    const Eigen::Vector3d t = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized() * l.t_m;
    const Eigen::Vector3d axis = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
    Eigen::Isometry3d d = Eigen::Isometry3d::Identity();
    d.linear() = Eigen::AngleAxisd(l.rot_deg * M_PI / 180, axis).toRotationMatrix();
    d.translation() = t;
    return T_world_cam * d;
}

struct ColumnResult
{
    std::string column;
    /** [level][frame]: counts summed over the frame's guesses (one at the true pose, `draws` otherwise). */
    std::array<std::vector<GuessResult>, kLevelCount> frames;
    std::array<int, kLevelCount> guesses_per_frame{};
    double wall_ms = 0, cpu_ms = 0;  ///< per frame (all its guesses)
    double ms_render = 0, ms_descriptors = 0, ms_search = 0, ms_xfeat = 0;
};

void accumulate(GuessResult& sum, const GuessResult& g)
{
    for (int i = 0; i < kCombos; ++i) sum.combos[size_t(i)].add(g.combos[size_t(i)]);
    for (int i = 0; i < kXFeatRows; ++i) sum.xfeat[size_t(i)].add(g.xfeat[size_t(i)]);
    sum.ms_render += g.ms_render, sum.ms_descriptors += g.ms_descriptors, sum.ms_search += g.ms_search;
    sum.ms_xfeat += g.ms_xfeat;
}

ColumnResult measure(const CrossModalSequence& seq, const std::string& column, const quasi::QuasiOptions& qo,
                     const MatchMainOptions& b, XFeatMatchers* xfeat)
{
    ColumnResult r;
    r.column = column;
    quasi::QuasiRenderer renderer(seq.map, qo);
    std::mt19937 rng(uint32_t(b.seed));
    const auto wall0 = std::chrono::steady_clock::now();
    const std::clock_t cpu0 = std::clock();
    for (const QueryFrame& f : seq.frames)
    {
        const CameraSide cam = describeCamera(f.image, b.m, xfeat);
        for (int l = 0; l < kLevelCount; ++l)
        {
            const int n = l == 0 ? 1 : b.draws;
            r.guesses_per_frame[size_t(l)] = n;
            GuessResult sum;
            for (int d = 0; d < n; ++d)
            {
                const Eigen::Isometry3d guess = l == 0 ? f.T_world_cam : perturb(f.T_world_cam, kLevels[l], rng);
                accumulate(sum, evaluateGuess(cam, seq.camera, seq.map, renderer, f.T_world_cam, guess, kLevels[l].t_m,
                                              kLevels[l].rot_deg, b.m, xfeat));
            }
            r.ms_render += sum.ms_render, r.ms_descriptors += sum.ms_descriptors, r.ms_search += sum.ms_search;
            r.ms_xfeat += sum.ms_xfeat;
            r.frames[size_t(l)].push_back(sum);
        }
        std::cout << "." << std::flush;
    }
    const double n = std::max<double>(1, double(seq.frames.size()));
    r.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall0).count() / n;
    r.cpu_ms = 1000.0 * double(std::clock() - cpu0) / CLOCKS_PER_SEC / n;
    r.ms_render /= n, r.ms_descriptors /= n, r.ms_search /= n, r.ms_xfeat /= n;
    std::cout << " " << column << ": " << seq.frames.size() << " frames\n";
    return r;
}

std::string fixed(double v, int precision)
{
    std::ostringstream s;
    s << std::fixed << std::setprecision(precision) << v;
    return s.str();
}

enum class CellKind
{
    Accepted,  ///< correct accepted matches, median per guess · precision
    Top1,      ///< best candidate correct, median per guess · share of keypoints
    Chance     ///< the same for a random candidate in the window
};

/** One row's figures in one column at one level. */
template <class Get>
std::string cell(const ColumnResult& r, int level, Get get, CellKind kind)
{
    std::vector<double> per_frame;
    MatchCounts total;
    for (const GuessResult& g : r.frames[size_t(level)])
    {
        const MatchCounts& c = get(g);
        total.add(c);
        const double v = kind == CellKind::Accepted ? double(c.correct)
                         : kind == CellKind::Top1   ? double(c.top1_correct)
                                                    : c.chance;
        per_frame.push_back(v / r.guesses_per_frame[size_t(level)]);
    }
    if (total.keypoints == 0) return "-";
    const std::string median = fixed(summarise(per_frame).median, 1) + " · ";
    const double keypoints = double(total.keypoints);
    if (kind == CellKind::Top1) return median + fixed(100.0 * double(total.top1_correct) / keypoints, 1) + " %";
    if (kind == CellKind::Chance) return median + fixed(100.0 * total.chance / keypoints, 1) + " %";
    return median +
           (total.accepted ? fixed(100.0 * double(total.correct) / double(total.accepted), 1) : std::string("-")) +
           " % (" + std::to_string(total.correct) + "/" + std::to_string(total.accepted) + ")";
}

void header(const std::vector<ColumnResult>& rs, const std::string& first)
{
    std::cout << "| " << first << " |";
    for (const auto& r : rs) std::cout << " " << r.column << " |";
    std::cout << "\n|---|";
    for (size_t i = 0; i < rs.size(); ++i) std::cout << "---|";
    std::cout << "\n";
}

void printTables(const std::vector<ColumnResult>& rs, const MatchMainOptions& b, const std::string& xfeat_status)
{
    std::cout << "\n## Frames, keypoints and time\n\n";
    header(rs, "");
    std::cout << "| frames |";
    for (const auto& r : rs) std::cout << " " << r.frames[0].size() << " |";
    for (int l = 0; l < kLevelCount; ++l)
    {
        std::cout << "\n| " << kLevels[l].name << ": map keypoints per guess, true position inside the window |";
        for (const auto& r : rs)
        {
            MatchCounts t;
            for (const auto& g : r.frames[size_t(l)]) t.add(g.combos[0]);
            const double guesses =
                double(std::max<size_t>(1, r.frames[size_t(l)].size())) * r.guesses_per_frame[size_t(l)];
            std::cout << " " << fixed(double(t.keypoints) / guesses, 0) << ", "
                      << fixed(100.0 * double(t.reachable) / double(std::max<long>(1, t.keypoints)), 1) << " % |";
        }
    }
    std::cout << "\n| time per frame (all guesses): wall / CPU [ms] |";
    for (const auto& r : rs) std::cout << " " << fixed(r.wall_ms, 0) << " / " << fixed(r.cpu_ms, 0) << " |";
    std::cout << "\n| of which render / map channels + keypoints / search / XFeat [ms] |";
    for (const auto& r : rs)
        std::cout << " " << fixed(r.ms_render, 0) << " / " << fixed(r.ms_descriptors, 0) << " / "
                  << fixed(r.ms_search, 0) << " / " << fixed(r.ms_xfeat, 0) << " |";
    std::cout << "\n";

    std::cout << "\n## " << kLevels[0].name
              << ": mean offset of the best candidate from the true position, dx / dy [px] (a systematic offset would "
                 "show a calibration or pose error)\n\n";
    header(rs, "camera / map channel / descriptor");
    for (int i = 0; i < kCombos; ++i)
    {
        std::cout << "| " << cameraVariantName(i / (kMapChannels * kKinds)) << " / "
                  << mapChannelName((i / kKinds) % kMapChannels) << " / " << frontend::toString(kindOf(i % kKinds))
                  << " |";
        for (const auto& r : rs)
        {
            MatchCounts t;
            for (const auto& g : r.frames[0]) t.add(g.combos[size_t(i)]);
            const double n = double(std::max<long>(1, t.found));
            std::cout << " " << fixed(t.sum_dx / n, 2) << " / " << fixed(t.sum_dy / n, 2) << " |";
        }
        std::cout << "\n";
    }
    std::cout << "\n## Share of the window's candidates that the true position beats (0.5: no information), mean over "
                 "keypoints: "
              << kLevels[0].name << " / " << kLevels[1].name << " / " << kLevels[2].name << "\n\n";
    header(rs, "camera / map channel / descriptor");
    for (int i = 0; i < kCombos; ++i)
    {
        std::cout << "| " << cameraVariantName(i / (kMapChannels * kKinds)) << " / "
                  << mapChannelName((i / kKinds) % kMapChannels) << " / " << frontend::toString(kindOf(i % kKinds))
                  << " |";
        for (const auto& r : rs)
        {
            std::cout << " ";
            for (int l = 0; l < kLevelCount; ++l)
            {
                MatchCounts t;
                for (const auto& g : r.frames[size_t(l)]) t.add(g.combos[size_t(i)]);
                std::cout << (l ? " / " : "") << (t.beaten_n ? fixed(t.beaten_sum / double(t.beaten_n), 3) : "-");
            }
            std::cout << " |";
        }
        std::cout << "\n";
    }
    for (int top1 = 0; top1 < 2; ++top1)
        for (int l = 0; l < kLevelCount; ++l)
        {
            std::cout << "\n## " << kLevels[l].name << ": "
                      << (top1 ? "best candidate correct, no ratio test: median per guess · share of keypoints"
                               : "accepted matches (ratio < " + fixed(b.m.ratio, 2) +
                                     "): correct, median per guess · precision (correct/accepted, all guesses)")
                      << "\n\n";
            header(rs, "camera / map channel / descriptor");
            for (int c = 0; c < kCameraVariants; ++c)
                for (int m = 0; m < kMapChannels; ++m)
                    for (int k = 0; k < kKinds; ++k)
                    {
                        std::cout << "| " << cameraVariantName(c) << " / " << mapChannelName(m) << " / "
                                  << frontend::toString(kindOf(k)) << " |";
                        const int i = comboIndex(c, m, k);
                        for (const auto& r : rs)
                            std::cout << " "
                                      << cell(
                                             r, l,
                                             [i](const GuessResult& g) -> const MatchCounts& {
                                                 return g.combos[size_t(i)];
                                             },
                                             top1 ? CellKind::Top1 : CellKind::Accepted)
                                      << " |";
                        std::cout << "\n";
                    }
            std::cout << "| random candidate in the window (chance) |";
            for (const auto& r : rs)
                std::cout << " "
                          << cell(
                                 r, l, [](const GuessResult& g) -> const MatchCounts& { return g.combos[0]; },
                                 CellKind::Chance)
                          << " |";
            std::cout << "\n";
            if (top1) continue;
            const char* names[kXFeatRows] = {"XFeat + LighterGlue, camera vs rank-equalised reflectivity (window)",
                                             "XFeat + mutual NN, camera vs rank-equalised reflectivity (window)"};
            for (int x = 0; x < kXFeatRows; ++x)
            {
                std::cout << "| " << names[x] << " |";
                for (const auto& r : rs)
                {
                    const std::string s = cell(
                        r, l, [x](const GuessResult& g) -> const MatchCounts& { return g.xfeat[size_t(x)]; },
                        CellKind::Accepted);
                    std::cout << " " << (s == "-" ? xfeat_status : s) << " |";
                }
                std::cout << "\n";
            }
        }
    std::cout << std::flush;
}

/** The XFeat extractor and matchers whose models exist; `status` says what is missing. */
XFeatMatchers makeXFeat(const MatchMainOptions& b, std::string& status)
{
    XFeatMatchers x;
    if (!std::filesystem::exists(b.xfeat_model))
    {
        status = "models not found (" + b.xfeat_model + ")";
        return x;
    }
    frontend::FeatureOptions fo;
    fo.type = frontend::FeatureType::XFeat;
    fo.xfeat_model_path = b.xfeat_model;
    fo.max_keypoints = b.xfeat_keypoints;
    fo.dense_map = false;
    fo.check("[BenchCrossModalMatch] xfeat_model");
    x.extractor = frontend::createFeatureExtractor(fo);
    frontend::PointMatchingOptions mo;
    mo.ratio = b.m.ratio;
    x.mutual_nn = frontend::createPointMatcher(mo);
    if (!frontend::lighterGlueAvailable())
        status = "LighterGlue: this build has no libtorch";
    else if (!std::filesystem::exists(b.lighterglue_model))
        status = "models not found (" + b.lighterglue_model + ")";
    else
    {
        mo.method = frontend::MatchingMethod::LighterGlue;
        mo.lighterglue_model = b.lighterglue_model;
        x.lighterglue = frontend::createPointMatcher(mo);
    }
    return x;
}

const char* kUsage =
    "Usage: bench_crossmodal_match [config.ini] [--set Section.key=value]...\n"
    "Correct camera/quasi-image correspondences per descriptor (NCC, MIND-SSC, orientation field), camera variant\n"
    "(raw, locally normalised) and map channel (reflectivity, rank-equalised, depth edges, both apart), and XFeat +\n"
    "LighterGlue, at the true pose and from guesses 0.1 m / 1 deg and 0.3 m / 3 deg off, on kitti_raw_seq78 and on\n"
    "simulated sequences. Sections: [BenchCrossModalMatch], [QuasiImage]. Run from the repository root.";

int run(const core::CommandLine& cmd_in)
{
    const core::CommandLine cmd = core::withOptionalConfig(cmd_in);
    const mrpt::config::CConfigFileMemory cfg = core::loadConfig(cmd);
    const std::string name = cmd.config_path.empty() ? "command line" : cmd.config_path;
    MatchMainOptions b;
    core::loadOptionsChecked(b, cfg, "BenchCrossModalMatch", name);
    quasi::QuasiOptions qo;
    core::loadOptionsChecked(qo, cfg, "QuasiImage", name);
    qo.check(name);

    std::cout << "# bench_crossmodal_match\n" << std::flush;
    std::string xfeat_status;
    XFeatMatchers xfeat = makeXFeat(b, xfeat_status);
    std::vector<ColumnResult> results;
    for (const std::string& kitti_map : b.kitti_frames >= 0 ? b.kitti_maps : std::vector<std::string>{})
    {
        const CrossModalSequence k =
            loadKittiSequence(b.kitti_dir, b.kitti_frames, kitti_map == "given" ? "" : kitti_map);
        const std::string column =
            "KITTI " +
            (kitti_map == "given" ? std::string("given map") : std::filesystem::path(kitti_map).stem().string()) +
            " (real)";
        quasi::QuasiOptions kq = qo;
        kq.max_depth_m = b.kitti_max_depth_m;
        results.push_back(measure(k, column, kq, b, &xfeat));
    }
    for (const std::string& materials : b.sim_materials)
    {
        const LabelledSequence s =
            loadLabelledSim(b.sim_dir, b.sim_world, materials, b.sim_start_offset_s, b.sim_duration_s, b.sim_frames);
        results.push_back(measure(s.seq, "sim " + materials + " (simulated)", qo, b, &xfeat));
    }
    core::require(!results.empty(), name, "nothing to measure: kitti_frames < 0 and no sim_materials");
    printTables(results, b, xfeat_status);
    return 0;
}
}  // namespace

int main(int argc, char** argv) { return core::runProgram(argc, argv, kUsage, run, false); }
