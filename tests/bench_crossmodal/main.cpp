// bench_crossmodal: pose refinement against the LiDAR map from perturbed poses, on the real KITTI raw
// sequence (../shared/data/kitti_raw_seq78) and on simulated frames, for every method of map_refinement.h.
// Prints success rate (< 0.1 m and < 0.5 deg), median final error, correct-match counts at the true pose and
// time per frame, per method and perturbation level.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/estimation/map_refinement.h>
#include <random>
#include <sstream>

#include "cost_profile.h"
#include "line_profile.h"
#include "kitti_sequence.h"
#include "sim_sequence.h"

namespace
{
using namespace quasiloc;

/** [BenchCrossModal] */
struct BenchOptions : public core::DeclaredOptions
{
    std::string kitti_dir = std::string(QUASILOC_SHARED_DIR) + "/data/kitti_raw_seq78";
    std::string kitti_map;  ///< empty: kitti_dir/map_even_frames_5cm.ply
    int kitti_frames = 0;   ///< 0: every query frame (39)
    double kitti_max_depth_m = 60;
    std::string sim_dir = "/tmp/quasiloc_bench_crossmodal/V1_01_easy_10s_2s";
    std::string sim_world = "share/quasiloc/sim/V1_01_easy.ini";
    int sim_frames = 8;
    int draws = 3;  ///< seeded random perturbations per frame and level
    std::string methods = "features,guided,direct,combined";
    double success_m = 0.1, success_deg = 0.5;
    double correct_px = 3.0;  ///< a 2D-3D correspondence is correct when the point projects this close at the true pose
    bool profile = true;      ///< print the cost profile of the direct terms (cost_profile.h)
    double profile_step_m = 0.1, profile_step_deg = 1.0;
    bool refine = true;         ///< run the refinements (false: the profile alone, for quick comparisons)
    bool from_truth = true;     ///< also refine from the true pose: where each method's optimum lies
    double line_window_px = 3;  ///< map-line profile: association window
    std::string
        overlay_dir;  ///< if set: per sequence, a PNG of the first frame's camera edges and map edges at the true pose

    void declare(core::OptionTable& t) override
    {
        const core::Range any = core::Range::any();
        t.add("kitti_dir", kitti_dir, "kitti_raw_seq78 folder");
        t.add("kitti_map", kitti_map,
              "the KITTI map: a LidarMap .map (map-build, map-import) or a cloud; empty: kitti_dir's "
              "map_even_frames_5cm.ply");
        t.add("kitti_frames", kitti_frames, "", any, "KITTI query frames (0: all 39; < 0: none)");
        t.add("kitti_max_depth_m", kitti_max_depth_m, "m", any, "quasi-image depth limit on KITTI");
        t.add("sim_dir", sim_dir, "simulated sequence (made from sim_world when missing)");
        t.add("sim_world", sim_world, "simulation INI");
        t.add("sim_frames", sim_frames, "", any, "simulated frames");
        t.add("draws", draws, "", any, "seeded random perturbations per frame and level");
        t.add("methods", methods, "comma-separated refinement methods");
        t.add("success_m", success_m, "m", any, "a refinement succeeds within this ...");
        t.add("success_deg", success_deg, "deg", any, "... and this");
        t.add("correct_px", correct_px, "px", any, "a 2D-3D correspondence is correct within this at the true pose");
        t.add("profile", profile, "print the cost profile of the direct terms");
        t.add("profile_step_m", profile_step_m, "m", any, "cost profile step");
        t.add("profile_step_deg", profile_step_deg, "deg", any, "cost profile step");
        t.add("refine", refine, "run the refinements (false: the profile alone)");
        t.add("from_truth", from_truth, "also refine from the true pose");
        t.add("overlay_dir", overlay_dir, "if set: camera and map edges of each sequence's first frame as PNG");
        t.add("line_window_px", line_window_px, "px", any, "map-line profile: association window");
    }
};

struct Level
{
    const char* name;
    double t_m, rot_deg;
};
const Level kLevels[] = {
    {"(a) 0.1 m / 1 deg", 0.1, 1.0}, {"(b) 0.3 m / 3 deg", 0.3, 3.0}, {"(c) 1 m / 5 deg", 1.0, 5.0}};

/** The true pose perturbed in the camera frame by exactly t_m along and rot_deg about random directions. */
Eigen::Isometry3d perturb(const Eigen::Isometry3d& T_world_cam, const Level& l, uint32_t seed)
{
    std::mt19937 rng(seed);
    std::normal_distribution<double> n;
    const Eigen::Vector3d t = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized() * l.t_m;
    const Eigen::Vector3d axis = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
    Eigen::Isometry3d d = Eigen::Isometry3d::Identity();
    d.linear() = Eigen::AngleAxisd(l.rot_deg * M_PI / 180, axis).toRotationMatrix();
    d.translation() = t;
    return T_world_cam * d;
}

double median(std::vector<double> v)
{
    if (v.empty()) return NAN;
    std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
    return v[v.size() / 2];
}

struct Cell
{
    int n = 0, ok = 0;
    std::vector<double> err_m, err_deg, ms;
};

/** Refinements started at the true pose: the offsets E = T_true^-1 * T_refined (camera frame: x right, y down,
 *  z forward). A term whose optimum is the truth returns near zero; a mean offset far from zero that does not
 *  shrink with the settings points at the term or at the reference poses. */
struct FromTruth
{
    int attempts = 0, n = 0, ok = 0;  // n: attempts that produced a pose (a failed one returns the start)
    Eigen::Vector3d sum_t = Eigen::Vector3d::Zero(), sum_w = Eigen::Vector3d::Zero();
    Eigen::Vector3d sq_t = Eigen::Vector3d::Zero(), sq_w = Eigen::Vector3d::Zero();
    void add(const Eigen::Isometry3d& E, bool success)
    {
        const Eigen::AngleAxisd aa(E.linear());
        const Eigen::Vector3d t = 100 * E.translation(), w = aa.angle() * 180 / M_PI * aa.axis();
        ++n, ok += success;
        sum_t += t, sum_w += w, sq_t += t.cwiseProduct(t), sq_w += w.cwiseProduct(w);
    }
    static std::string meanSpread(const Eigen::Vector3d& sum, const Eigen::Vector3d& sq, int n, int precision)
    {
        std::ostringstream s;
        s << std::fixed << std::setprecision(precision);
        const Eigen::Vector3d m = sum / std::max(1, n);
        for (int i = 0; i < 3; ++i)
            s << (i ? " / " : "") << m[i] << " ± " << std::sqrt(std::max(0.0, sq[i] / std::max(1, n) - m[i] * m[i]));
        return s.str();
    }
};

/** An offset E = T_true^-1 * T_refined within the success bounds. */
bool withinSuccess(const Eigen::Isometry3d& E, const BenchOptions& b)
{
    return E.translation().norm() < b.success_m && Eigen::AngleAxisd(E.linear()).angle() * 180 / M_PI < b.success_deg;
}

int correctCount(const estimation::MapRefinementResult& r, const Eigen::Isometry3d& T_world_cam,
                 const core::CameraModel& cam, double tol)
{
    const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();
    int n = 0;
    for (size_t i = 0; i < r.points2d.size(); ++i)
    {
        Eigen::Vector2d u;
        n += cam.project(T_cam_world * r.points3d[i], u) && (u - r.points2d[i]).norm() <= tol;
    }
    return n;
}

/** Camera Canny edges (red) and the direct-alignment model's edge points projected at the true pose (green),
 *  above the quasi-image: what the direct term sees. */
void writeOverlay(const std::string& path, const bench::QueryFrame& fr, const core::CameraModel& cam,
                  quasi::QuasiRenderer& renderer, const estimation::DirectAlignmentOptions& o)
{
    quasi::QuasiImage q;
    renderer.render(core::fromIsometry(fr.T_world_cam), cam, q);
    const auto field = estimation::buildCameraEdgeField(o, fr.image);
    const auto model =
        estimation::buildDirectAlignmentModel(o, q.depth, q.reflectivity, q.valid, q.sparse, cam, fr.T_world_cam);
    cv::Mat vis;
    cv::cvtColor(field.gray, vis, cv::COLOR_GRAY2BGR);
    vis.setTo(cv::Scalar(0, 0, 255), field.levels[0].edges);
    const Eigen::Isometry3d T_cam_world = fr.T_world_cam.inverse();
    for (const auto& P : model.edge_points_world)
    {
        Eigen::Vector2d u;
        if (cam.project(T_cam_world * P, u))
            cv::circle(vis, cv::Point(int(u.x()), int(u.y())), 1, cv::Scalar(0, 255, 0), -1);
    }
    cv::Mat out;
    cv::vconcat(vis, q.bgr, out);
    cv::imwrite(path, out);
    std::cout << "overlay written to " << path << std::endl;
}

std::vector<std::string> split(const std::string& s)
{
    std::vector<std::string> out;
    std::stringstream in(s);
    for (std::string item; std::getline(in, item, ',');)
        if (!item.empty()) out.push_back(item);
    return out;
}

void runSequence(const bench::CrossModalSequence& seq, const BenchOptions& b, const quasi::QuasiOptions& qo,
                 const frontend::FrontendOptions& fo, const estimation::MapRefinementOptions& ro)
{
    std::vector<estimation::RefinementMethod> methods;
    for (const auto& m : split(b.methods)) methods.push_back(estimation::refinementMethodFromString(m, "methods"));
    quasi::QuasiRenderer renderer(seq.map, qo);
    frontend::Frontend frontend(fo);
    estimation::MapRefiner refiner(ro, renderer, frontend);

    if (!b.overlay_dir.empty())
        writeOverlay(b.overlay_dir + "/" + seq.name + "_edges.png", seq.frames.front(), seq.camera, renderer,
                     ro.direct);
    if (b.profile)
    {
        const bench::CostProfile p =
            bench::profileDirectTerms(seq, renderer, ro.direct, b.profile_step_m, b.profile_step_deg, frontend,
                                      ro.quasi_gray == estimation::QuasiGray::MatchedReflectivity);
        std::cout << "\n## " << seq.name << ": cost profile at the true pose (" << seq.frames.size()
                  << " frames x 12 steps of " << b.profile_step_m << " m / " << b.profile_step_deg << " deg)\n\n"
                  << "| valid pixels | edge points | edge cost lowest at truth | mean edge cost rise | NMI highest at "
                     "truth | mean NMI drop | feature-metric highest at truth | mean feature-metric drop |\n"
                  << "|---|---|---|---|---|---|---|---|\n"
                  << std::fixed << std::setprecision(1) << "| " << 100 * p.mean_valid_fraction << " % | "
                  << p.mean_edge_points << " | " << 100.0 * p.edge_truth_best / std::max(1, p.steps) << " % | "
                  << std::setprecision(3) << 100 * p.mean_edge_rise << " % | " << std::setprecision(1)
                  << 100.0 * p.nmi_truth_best / std::max(1, p.steps) << " % | " << std::setprecision(4)
                  << p.mean_nmi_drop << " | ";
        if (p.fm_truth_best < 0)
            std::cout << "- | - |\n\n";
        else
            std::cout << std::setprecision(1) << 100.0 * p.fm_truth_best / std::max(1, p.steps) << " % | "
                      << std::setprecision(4) << p.mean_fm_drop << " |\n\n";
        const bench::LineProfile lp =
            bench::profileMapLines(seq, renderer, fo.lines, b.line_window_px, b.profile_step_m, b.profile_step_deg);
        std::cout << "Map lines (normal shading of the quasi-image at the true pose, tracking/map_lines.h) against the "
                     "camera's segments, associated by geometry within "
                  << b.line_window_px << " px:\n\n"
                  << "| camera segments | map lines | segments associated at the truth | one step away | truth "
                     "associates more |\n"
                  << "|---|---|---|---|---|\n"
                  << std::setprecision(1) << "| " << lp.camera_segments << " | " << lp.map_lines << " | "
                  << lp.associated_at_truth << " | " << lp.associated_one_step << " | "
                  << 100.0 * lp.truth_more / std::max(1, lp.steps) << " % |\n\n";
        std::cout << std::flush;
    }
    if (!b.refine) return;
    std::map<std::pair<int, int>, Cell> cells;  // (method, level)
    std::vector<FromTruth> from_truth(methods.size());
    double image_ms = 0, matches_f = 0, correct_f = 0, matches_g = 0, correct_g = 0;
    for (size_t fi = 0; fi < seq.frames.size(); ++fi)
    {
        const bench::QueryFrame& fr = seq.frames[fi];
        refiner.setImage(fr.image, seq.camera);
        image_ms += refiner.lastImageMs();
        // Refinements started at the true pose with the (a) level's window, each method once per frame: the correct
        // matches (the prediction is exact: what each matcher can give PnP) and where each method ends. Without the
        // prediction prior: at the truth it would sit on the answer and hold the pose there, and the table is to
        // show where each method's own cost has its optimum.
        std::map<estimation::RefinementMethod, estimation::MapRefinementResult> at_truth;
        const auto atTruth = [&](estimation::RefinementMethod m) -> const estimation::MapRefinementResult& {
            auto it = at_truth.find(m);
            if (it == at_truth.end())
            {
                const double sigma_rad = kLevels[0].rot_deg * M_PI / 180;
                it = at_truth.emplace(m, refiner.refine(m, fr.T_world_cam, kLevels[0].t_m, sigma_rad, 0.0)).first;
            }
            return it->second;
        };
        const auto& rf = atTruth(estimation::RefinementMethod::Features);
        const auto& rg = atTruth(estimation::RefinementMethod::Guided);
        matches_f += rf.matches, correct_f += correctCount(rf, fr.T_world_cam, seq.camera, b.correct_px);
        matches_g += rg.matches, correct_g += correctCount(rg, fr.T_world_cam, seq.camera, b.correct_px);
        if (b.from_truth)
            for (size_t mi = 0; mi < methods.size(); ++mi)
            {
                const auto& r = atTruth(methods[mi]);
                ++from_truth[mi].attempts;
                if (!r.success) continue;
                const Eigen::Isometry3d E = fr.T_world_cam.inverse() * r.T_world_cam;
                from_truth[mi].add(E, withinSuccess(E, b));
            }
        for (int li = 0; li < 3; ++li)
            for (int d = 0; d < b.draws; ++d)
            {
                const Eigen::Isometry3d T0 =
                    perturb(fr.T_world_cam, kLevels[li], uint32_t(1000 * fi + 10 * li + d + 1));
                for (size_t mi = 0; mi < methods.size(); ++mi)
                {
                    const auto r = refiner.refine(methods[mi], T0, kLevels[li].t_m, kLevels[li].rot_deg * M_PI / 180);
                    const Eigen::Isometry3d E = fr.T_world_cam.inverse() * r.T_world_cam;
                    const double em = E.translation().norm();
                    const double ed = Eigen::AngleAxisd(E.linear()).angle() * 180 / M_PI;
                    Cell& c = cells[{int(mi), li}];
                    ++c.n;
                    c.ok += withinSuccess(E, b);
                    c.err_m.push_back(em), c.err_deg.push_back(ed), c.ms.push_back(r.ms_total);
                }
            }
        std::cout << "." << std::flush;
    }
    const double nf = double(seq.frames.size());
    std::cout << "\n\n## " << seq.name << ": " << seq.frames.size() << " query frames x " << b.draws
              << " draws per level, " << seq.map.size() << " map points, " << seq.camera.width << "x"
              << seq.camera.height << "\n\n";
    std::cout
        << "success = final error < " << b.success_m << " m and < " << b.success_deg
        << " deg; time = the refinement (render, Q features, matching, PnP, direct) per attempt; the camera image's "
           "own features and edge field take "
        << std::fixed << std::setprecision(1) << image_ms / nf << " ms once per frame\n\n";
    if (b.draws > 0)
        std::cout
            << "| method | perturbation | success | median error [cm] | median error [deg] | mean time [ms] | max time "
               "[ms] |\n|---|---|---|---|---|---|---|\n";
    for (size_t mi = 0; mi < methods.size() && b.draws > 0; ++mi)
        for (int li = 0; li < 3; ++li)
        {
            const Cell& c = cells[{int(mi), li}];
            double mean_ms = 0, max_ms = 0;
            for (double t : c.ms) mean_ms += t / double(c.ms.size()), max_ms = std::max(max_ms, t);
            std::cout << "| " << estimation::toString(methods[mi]) << " | " << kLevels[li].name << " | "
                      << std::setprecision(1) << 100.0 * c.ok / std::max(1, c.n) << " % (" << c.ok << "/" << c.n
                      << ") | " << 100 * median(c.err_m) << " | " << std::setprecision(2) << median(c.err_deg) << " | "
                      << std::setprecision(1) << mean_ms << " | " << max_ms << " |\n";
        }
    if (b.from_truth)
    {
        std::cout << "\nStarted at the true pose (window of level (a), no prediction prior: the direct term's own "
                     "optimum): where each method ends, E = T_true^-1 * "
                     "T_refined in the camera frame (x right, y down, z forward), mean ± standard deviation over the "
                     "frames that produced a pose (success: of all frames)\n\n| method | produced a pose | success | "
                     "translation x / y / z [cm] | rotation about x / y / z [deg] |\n"
                     "|---|---|---|---|---|\n";
        for (size_t mi = 0; mi < methods.size(); ++mi)
        {
            const FromTruth& t = from_truth[mi];
            std::cout << "| " << estimation::toString(methods[mi]) << " | " << t.n << "/" << t.attempts << " | " << t.ok
                      << "/" << t.attempts << " | ";
            if (t.n == 0)
                std::cout << "- | - |\n";
            else
                std::cout << FromTruth::meanSpread(t.sum_t, t.sq_t, t.n, 1) << " | "
                          << FromTruth::meanSpread(t.sum_w, t.sq_w, t.n, 2) << " |\n";
        }
    }
    std::cout << "\nCorrect 2D-3D correspondences at the true pose (within " << b.correct_px
              << " px), per frame: features (whole image, mutual NN + ratio) " << std::setprecision(1) << correct_f / nf
              << " of " << matches_f / nf << "; guided (window of the (a) level, " << ro.guided_candidates
              << " candidates) " << correct_g / nf << " of " << matches_g / nf << "\n";
}

const char* kUsage =
    "Usage: bench_crossmodal [config.ini] [--set Section.key=value]... [--print-timing]\n"
    "Refines perturbed poses against the LiDAR map on kitti_raw_seq78 and on simulated frames with each method\n"
    "(features, guided, direct, combined) and prints success rates, errors, match counts and times.\n"
    "Sections: [BenchCrossModal], [MapRefinement], [DirectAlignment], [QuasiImage], [Features], [PointMatching], ...\n"
    "Run from the repository root.";

int run(const core::CommandLine& cmd_in)
{
    const core::CommandLine cmd = core::withOptionalConfig(cmd_in);
    const mrpt::config::CConfigFileMemory cfg = core::loadConfig(cmd);  // overrides alone without an INI file
    const std::string name = cmd.config_path.empty() ? "command line" : cmd.config_path;
    BenchOptions b;
    core::loadOptionsChecked(b, cfg, "BenchCrossModal", name);
    frontend::FrontendOptions fo;
    fo.load(cfg, name);
    quasi::QuasiOptions qo;
    core::loadOptionsChecked(qo, cfg, "QuasiImage", name);
    qo.check(name);
    estimation::MapRefinementOptions ro;
    core::loadOptionsChecked(ro.direct, cfg, "DirectAlignment", name);  // unknown-key check of that section
    core::loadOptionsChecked(ro, cfg, "MapRefinement", name);           // (loads [DirectAlignment] too)
    ro.check(name);

    std::cout << "# bench_crossmodal (features: " << frontend::toString(fo.features.type) << ")\n" << std::flush;
    if (b.kitti_frames >= 0)
    {
        quasi::QuasiOptions kq = qo;
        kq.max_depth_m = b.kitti_max_depth_m;
        runSequence(bench::loadKittiSequence(b.kitti_dir, b.kitti_frames, b.kitti_map), b, kq, fo, ro);
    }
    if (b.sim_frames > 0)
        runSequence(bench::loadSimSequence(b.sim_dir, b.sim_world, 10.0, 2.0, b.sim_frames), b, qo, fo, ro);
    return 0;
}
}  // namespace

int main(int argc, char** argv) { return core::runProgram(argc, argv, kUsage, run, false); }
