// Part 1 of bench_frontend: camera image <-> quasi-image on simulated sequences.
//
// For every selected frame the quasi-image Q is rendered from the LiDAR map with the left camera's model at the
// ground-truth pose and at a perturbed pose (perturb_translation_m along a random direction and
// perturb_rotation_deg about a random axis, seeded by the frame index). Camera keypoints are matched to Q's
// within cross_modal_window_px, camera lines to Q's lines with the geometric gate.
// Correctness (precision_px, 3 px by default): a point match is correct when the Q keypoint, lifted through
// provenance to its LiDAR point, projects at the ground-truth pose within precision_px of the camera keypoint.
// A line match is correct when the LiDAR support of the Q line projects at the ground-truth pose with median
// distance <= precision_px to the camera segment's line and its extent along the segment overlaps it.
// Associations: K candidates per matched feature; "any ok" = some candidate is correct; "p on ok" = the mean
// probability mass the distribution puts on correct candidates.
// LighterGlue (libtorch builds, with the model file, when xfeat is measured): the same XFeat features of every
// camera<->quasi pair matched by the network over the whole image, counted as is ("whole image") and gated by the
// same window as mutual NN ("window"), with the same correctness rule; time per pair (the network sees every keypoint
// of both images whichever gate follows).
#include <dirent.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <sys/stat.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <iostream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/dataset/frame_source.h>
#include <quasiloc/frontend/lifting.h>
#include <quasiloc/frontend/plane_hypotheses.h>
#include <quasiloc/frontend/point_matcher.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <quasiloc/sim/simulation.h>
#include <random>

#include "bench_common.h"

namespace quasiloc::bench
{
namespace
{
using frontend::FrameFeatures;
using mrpt::poses::CPose3D;

bool fileExists(const std::string& p)
{
    struct stat st;
    return ::stat(p.c_str(), &st) == 0;
}

std::vector<std::string> split(const std::string& s)
{
    BenchOptions tmp;
    tmp.extractors = s;
    return tmp.extractorList();
}

/** The sim-rawlog folders: [Bench] sim_dirs, or sim_worlds simulated into sim_root (reused when complete). */
std::vector<std::string> simulatedDirs(const BenchOptions& b)
{
    if (!b.sim_dirs.empty()) return split(b.sim_dirs);
    std::vector<std::string> dirs;
    for (const auto& world : split(b.sim_worlds))
    {
        std::string stem = world.substr(world.find_last_of('/') + 1);
        stem = stem.substr(0, stem.find('.'));
        const std::string out =
            b.sim_root + "/" + stem + "_" + fmt(b.sim_start_offset_s, 1) + "s_" + fmt(b.sim_duration_s, 1) + "s";
        if (!fileExists(out + "/gt.tum") || !fileExists(out + "/lidar_map.map"))
        {
            core::CommandLine cmd;
            cmd.config_path = world;
            cmd.overrides = {{"Simulation.output_dir", out},
                             {"Simulation.duration_s", fmt(b.sim_duration_s, 3)},
                             {"Simulation.start_offset_s", fmt(b.sim_start_offset_s, 3)},
                             {"Simulation.inspection_png", "false"},
                             {"Simulation.verbose", "false"}};
            std::cout << "simulating " << world << " into " << out << " ..." << std::endl;
            sim::runSimulation(core::loadConfig(cmd), world);
        }
        else
            std::cout << "reusing the simulated sequence " << out << " (delete it to simulate again)" << std::endl;
        dirs.push_back(out);
    }
    return dirs;
}

std::string findRawlog(const std::string& dir)
{
    DIR* d = ::opendir(dir.c_str());
    core::require(d != nullptr, dir, "cannot open the sim-rawlog folder");
    std::string found;
    while (dirent* e = ::readdir(d))
    {
        const std::string n = e->d_name;
        if (n.size() > 7 && n.substr(n.size() - 7) == ".rawlog") found = dir + "/" + n;
    }
    ::closedir(d);
    core::require(!found.empty(), dir, "no .rawlog in the folder");
    return found;
}

CPose3D perturb(const CPose3D& T, const BenchOptions& b, uint32_t seed)
{
    std::mt19937 rng(seed);
    std::normal_distribution<double> n(0, 1);
    const Eigen::Vector3d t = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized() * b.perturb_translation_m;
    const Eigen::Vector3d axis = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
    Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();
    delta.linear() = Eigen::AngleAxisd(b.perturb_rotation_deg * M_PI / 180, axis).toRotationMatrix();
    delta.translation() = t;
    return T + core::fromIsometry(delta);  // the perturbation in the camera frame
}

bool projectAt(const CPose3D& T_world_cam, const core::CameraModel& cam, const Eigen::Vector3f& p, Eigen::Vector2d& u)
{
    double X, Y, Z;
    T_world_cam.inverseComposePoint(p.x(), p.y(), p.z(), X, Y, Z);
    return cam.project({X, Y, Z}, u) && cam.isInImage(u, -50);
}

bool pointCorrect(const Eigen::Vector3f& p, const cv::Point2f& kp, const CPose3D& T_gt, const core::CameraModel& cam,
                  double tol)
{
    Eigen::Vector2d u;
    return projectAt(T_gt, cam, p, u) && std::hypot(u.x() - kp.x, u.y() - kp.y) <= tol;
}

bool lineCorrect(const frontend::LineSupport& s, const frontend::LineSegment& l, const CPose3D& T_gt,
                 const core::CameraModel& cam, double tol)
{
    if (!s.valid()) return false;
    std::vector<float> dist;
    float tmin = 1e9f, tmax = -1e9f;
    for (const auto& p : s.points)
    {
        Eigen::Vector2d u;
        if (!projectAt(T_gt, cam, p, u)) continue;
        dist.push_back(l.distanceToLine(u.cast<float>()));
        const float t = (u.cast<float>() - l.p0).dot(l.direction());
        tmin = std::min(tmin, t), tmax = std::max(tmax, t);
    }
    if (dist.size() < 2) return false;
    std::nth_element(dist.begin(), dist.begin() + dist.size() / 2, dist.end());
    return dist[dist.size() / 2] <= tol && tmax >= 0 && tmin <= l.length();
}

struct Frame
{
    cv::Mat left;
    CPose3D T_world_cam0;
};

struct CaseStats
{
    double frames = 0, kp_cam = 0, kp_q = 0, pm = 0, pm_lifted = 0, pm_ok = 0;
    double lines_cam = 0, lines_q = 0, lm = 0, lm_ok = 0;
    double pa = 0, pa_cands = 0, pa_any = 0, pa_pmass = 0;
    double la = 0, la_cands = 0, la_any = 0, la_planes = 0;
};

/** Point matches of one matcher: count, lifted, correct (the nominal of each match). */
struct MatchStats
{
    double frames = 0, pm = 0, pm_lifted = 0, pm_ok = 0;
};

struct Sequence
{
    std::string dir;
    map::LidarMap map;
    core::StereoRig rig;
    std::vector<Frame> frames;
};

Sequence loadSequence(const std::string& dir, int wanted)
{
    Sequence s;
    s.dir = dir;
    s.map = map::LidarMap::load(dir + "/lidar_map.map");
    dataset::FrameSourceOptions fo;
    fo.groundtruth_tum = dir + "/gt.tum";
    fo.calibration_ini = dir + "/calib.ini";
    auto src = dataset::openRawlog(findRawlog(dir), fo);
    s.rig = src->rig();
    std::vector<Frame> all;
    dataset::StereoFrame f;
    while (src->next(f))
        if (f.T_world_cam0) all.push_back(Frame{f.left.clone(), *f.T_world_cam0});
    core::require(!all.empty(), dir, "no frame with ground truth");
    for (int k = 0; k < wanted && k < int(all.size()); ++k)
        s.frames.push_back(all[size_t(k) * all.size() / size_t(std::min<int>(wanted, int(all.size())))]);
    return s;
}

/** One camera frame against one quasi-image: matches, precision, associations (timed). */
void evaluatePair(const FrameFeatures& fi, const quasi::QuasiImage& q, const FrameFeatures& fq, const Sequence& seq,
                  const CPose3D& T_gt, const frontend::FrontendOptions& o, const BenchOptions& b, StageTimes& times,
                  const std::string& type, CaseStats& st)
{
    const auto& cam = seq.rig.left;
    frontend::SearchRegion region;
    region.radius_px = b.cross_modal_window_px;
    Stopwatch sw_pm;
    std::vector<frontend::PointCandidate> best_q;
    const auto cands = frontend::findCandidates(fi.points, fq.points, std::max(2, o.association.max_candidates),
                                                o.point_matching.maxDistance(fi.points), region, &best_q);
    const auto pm = frontend::selectMatches(cands, best_q, o.point_matching);
    times.add(type + " match points (cross-modal)", sw_pm.ms());
    Stopwatch sw_lm;
    const auto lm =
        frontend::matchLines(fi.line_descriptors, fi.lines, fq.line_descriptors, fq.lines, o.line_matching, true);
    times.add(type + " match lines (cross-modal)", sw_lm.ms());

    Stopwatch sw_as;
    const auto pa = frontend::pointAssociations(pm, cands, o.association);
    std::vector<std::vector<std::optional<frontend::LiftedPoint>>> lifted(pa.size());
    for (size_t k = 0; k < pa.size(); ++k)
        for (const auto& c : pa[k].candidates)
            lifted[k].push_back(frontend::liftPixel(q, seq.map, fq.points.keypoints[size_t(c.index)].pt,
                                                    o.association.lift_search_radius_px));
    const double ms_points = sw_as.ms();
    const auto la = frontend::lineAssociations(lm, o.association);
    const auto lh = frontend::liftLineAssociations(la, q, seq.map, fq.lines, o.association);
    const double ms_all = sw_as.ms();
    times.add(type + " associations (lift + planes)", ms_all);
    times.add(type + "   of which points (distributions + lifting)", ms_points);
    times.add(type + "   of which lines (distributions + support + planes)", ms_all - ms_points);

    st.frames += 1;
    st.kp_cam += double(fi.points.size()), st.kp_q += double(fq.points.size());
    st.lines_cam += double(fi.lines.size()), st.lines_q += double(fq.lines.size());
    for (size_t k = 0; k < pa.size(); ++k)
    {
        const cv::Point2f kp = fi.points.keypoints[size_t(pa[k].query)].pt;
        st.pa += 1, st.pm += 1, st.pa_cands += double(pa[k].candidates.size());
        bool any = false;
        for (size_t c = 0; c < pa[k].candidates.size(); ++c)
        {
            const bool ok = lifted[k][c] && pointCorrect(lifted[k][c]->p_world, kp, T_gt, cam, b.precision_px);
            if (c == 0) st.pm_lifted += lifted[k][c].has_value(), st.pm_ok += ok;
            any |= ok;
            if (ok) st.pa_pmass += pa[k].candidates[c].probability;
        }
        st.pa_any += any;
    }
    for (size_t k = 0; k < la.size(); ++k)
    {
        const auto& cam_line = fi.lines[size_t(la[k].query)];
        st.la += 1, st.lm += 1, st.la_cands += double(lh[k].size());
        bool any = false;
        for (size_t c = 0; c < lh[k].size(); ++c)
        {
            const bool ok = lineCorrect(lh[k][c].support, cam_line, T_gt, cam, b.precision_px);
            if (c == 0) st.lm_ok += ok;
            any |= ok;
            st.la_planes += double(lh[k][c].planes.size());
        }
        st.la_any += any;
    }
}
/** XFeat + LighterGlue on one camera<->quasi pair (see the top of the file). */
void evaluateLighterGlue(frontend::PointMatcher& lighterglue, const FrameFeatures& fi, const quasi::QuasiImage& q,
                         const FrameFeatures& fq, const Sequence& seq, const CPose3D& T_gt,
                         const frontend::FrontendOptions& o, const BenchOptions& b, StageTimes& times,
                         MatchStats& whole, MatchStats& windowed)
{
    Stopwatch sw;
    const auto matches = lighterglue.match(fi.points, fq.points);
    times.add("xfeat+lighterglue match points (cross-modal)", sw.ms());
    whole.frames += 1, windowed.frames += 1;
    for (const auto& m : matches)
    {
        const auto lifted = frontend::liftPixel(q, seq.map, fq.points.keypoints[size_t(m.train)].pt,
                                                o.association.lift_search_radius_px);
        const bool ok = lifted && pointCorrect(lifted->p_world, fi.points.keypoints[size_t(m.query)].pt, T_gt,
                                               seq.rig.left, b.precision_px);
        const cv::Point2f d = fq.points.keypoints[size_t(m.train)].pt - fi.points.keypoints[size_t(m.query)].pt;
        const bool in_window = std::hypot(d.x, d.y) <= b.cross_modal_window_px;  // the mutual NN search window
        for (MatchStats* st : {&whole, &windowed})
            if (st == &whole || in_window) st->pm += 1, st->pm_lifted += lifted.has_value(), st->pm_ok += ok;
    }
}

/** The LighterGlue matcher for the bench, or nullptr (and why) when it cannot run here. */
std::unique_ptr<frontend::PointMatcher> lighterGlueFor(const BenchOptions& b, const std::vector<std::string>& types,
                                                       std::string& why_not)
{
    if (std::find(types.begin(), types.end(), "xfeat") == types.end())
        why_not = "xfeat is not measured";
    else if (!frontend::lighterGlueAvailable())
        why_not = "this build has no libtorch";
    else if (!fileExists(b.lighterglue_model))
        why_not = "no model file " + b.lighterglue_model;
    if (!why_not.empty()) return nullptr;
    frontend::PointMatchingOptions o;
    o.method = frontend::MatchingMethod::LighterGlue;
    o.lighterglue_model = b.lighterglue_model;
    return frontend::createPointMatcher(o);  // whole image: the window is applied when counting
}

void reportLighterGlue(const std::map<std::string, CaseStats>& stats, const std::map<std::string, MatchStats>& lg,
                       const StageTimes& times, const BenchOptions& b, Report& report)
{
    report.line(
        "XFeat + LighterGlue vs XFeat + mutual NN, camera <-> quasi-image (point matches per frame; correct "
        "within " +
        fmt(b.precision_px, 1) + " px at the gt pose; time per pair):");
    report.line("");
    report.line("| matcher | Q pose | point matches | correct | precision | ms per pair (mean / max) |");
    report.line("|---|---|---|---|---|---|");
    auto timing = [&](const std::string& stage) {
        const auto it = times.stats().find(stage);
        return it == times.stats().end() ? std::string("-")
                                         : fmt(it->second.mean(), 1) + " / " + fmt(it->second.max, 1);
    };
    for (const std::string which : {"gt pose", "perturbed"})
    {
        const auto nn = stats.find("xfeat|" + which);
        if (nn != stats.end())
        {
            const double n = std::max(1.0, nn->second.frames);
            report.line("| mutual NN, window " + fmt(b.cross_modal_window_px, 0) + " px | " + which + " | " +
                        fmt(nn->second.pm / n, 1) + " | " + fmt(nn->second.pm_ok / n, 1) + " | " +
                        pct(nn->second.pm_ok, nn->second.pm) + " | " + timing("xfeat match points (cross-modal)") +
                        " |");
        }
        for (const std::string gate : {"window", "whole image"})
        {
            const auto it = lg.find(gate + "|" + which);
            if (it == lg.end()) continue;
            const double n = std::max(1.0, it->second.frames);
            const std::string label = gate == "window"
                                          ? "LighterGlue, window " + fmt(b.cross_modal_window_px, 0) + " px"
                                          : std::string("LighterGlue, whole image");
            report.line("| " + label + " | " + which + " | " + fmt(it->second.pm / n, 1) + " | " +
                        fmt(it->second.pm_ok / n, 1) + " | " + pct(it->second.pm_ok, it->second.pm) + " | " +
                        timing("xfeat+lighterglue match points (cross-modal)") + " |");
        }
    }
    report.line("");
}
}  // namespace

void runCrossModal(const mrpt::config::CConfigFileBase&, const BenchOptions& b, const frontend::FrontendOptions& base,
                   const quasi::QuasiOptions& qo, mrpt::system::CTimeLogger& logger, Report& report)
{
    StageTimes times(logger);
    std::map<std::string, CaseStats> stats;  // "<type>|<case>"
    std::vector<std::string> types, skipped;
    for (const auto& t : b.extractorList())
        if (t != "xfeat" || fileExists(withExtractor(base, t, b).features.xfeat_model_path))
            types.push_back(t);
        else
            skipped.push_back(t);
    std::string lighterglue_skipped;
    const auto lighterglue = lighterGlueFor(b, types, lighterglue_skipped);
    std::map<std::string, MatchStats> lg_stats;  // "<gate>|<case>"
    bool lighterglue_warm = false;
    std::vector<std::string> seq_names;
    for (const auto& dir : simulatedDirs(b))
    {
        const Sequence seq = loadSequence(dir, b.frames_per_sequence);
        seq_names.push_back(dir + " (" + std::to_string(seq.frames.size()) + " frames, " +
                            std::to_string(seq.map.size()) + " map points)");
        quasi::QuasiRenderer renderer(seq.map, qo);
        for (const auto& type : types)
        {
            frontend::Frontend fe(withExtractor(base, type, b));
            for (size_t k = 0; k < seq.frames.size(); ++k)
            {
                const Frame& fr = seq.frames[k];
                FrameFeatures fi;
                fe.extract(fr.left, cv::Mat(), fi);
                for (const std::string which : {"gt pose", "perturbed"})
                {
                    const CPose3D T_render = which == std::string("gt pose")
                                                 ? fr.T_world_cam0
                                                 : perturb(fr.T_world_cam0, b, uint32_t(k + 1));
                    quasi::QuasiImage q;
                    renderer.render(T_render, seq.rig.left, q);
                    FrameFeatures fq;
                    Stopwatch sw_p;
                    fe.extract(q.gray, q.valid, fq);
                    times.add(type + " extract quasi-image (points + lines)", sw_p.ms());
                    times.add(type + "   of which points (quasi)", fq.points_ms);
                    times.add(type + "   of which lines (quasi)", fq.lines_ms);
                    if (which == std::string("gt pose"))
                    {
                        times.add(type + " extract camera image (points + lines)", fi.total_ms);
                    }
                    evaluatePair(fi, q, fq, seq, fr.T_world_cam0, fe.options(), b, times, type,
                                 stats[type + "|" + which]);
                    if (type == "xfeat" && lighterglue)
                    {
                        // TorchScript optimises its graph during the first runs: keep them out of the timing.
                        for (; !lighterglue_warm; lighterglue_warm = true)
                            for (int k = 0; k < 3; ++k) lighterglue->match(fi.points, fq.points);
                        evaluateLighterGlue(*lighterglue, fi, q, fq, seq, fr.T_world_cam0, fe.options(), b, times,
                                            lg_stats["whole image|" + which], lg_stats["window|" + which]);
                    }
                }
            }
        }
    }
    report.line("## Camera <-> quasi-image (simulated sequences)");
    report.line("");
    for (const auto& s : seq_names) report.line("- " + s);
    if (!skipped.empty()) report.line("- skipped (no XFeat model file): xfeat");
    if (!lighterglue_skipped.empty()) report.line("- XFeat + LighterGlue not measured: " + lighterglue_skipped);
    report.line("- window " + fmt(b.cross_modal_window_px, 0) + " px (points), line gate " +
                fmt(base.line_matching.gate_max_distance_px, 0) + " px / " +
                fmt(base.line_matching.gate_max_angle_deg, 0) +
                " deg; correct = lifted LiDAR point (line support) within " + fmt(b.precision_px, 1) +
                " px of the camera keypoint (line) at the gt pose; perturbation " +
                fmt(100 * b.perturb_translation_m, 0) + " cm / " + fmt(b.perturb_rotation_deg, 1) + " deg");
    report.line("- per frame means; K = " + std::to_string(base.association.max_candidates) +
                " candidates, temperature " + fmt(base.association.temperature, 3));
    report.line("");
    report.line(
        "| extractor | Q pose | kp cam / Q | point matches | correct | precision | lines cam / Q | line matches | "
        "correct | precision | pt cand | pt any ok | p on ok | line cand | line any ok | planes / line hyp |");
    report.line("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for (const auto& type : types)
        for (const std::string which : {"gt pose", "perturbed"})
        {
            const CaseStats& s = stats[type + "|" + which];
            const double n = std::max(1.0, s.frames);
            report.line("| " + type + " | " + which + " | " + fmt(s.kp_cam / n, 0) + " / " + fmt(s.kp_q / n, 0) +
                        " | " + fmt(s.pm / n, 1) + " | " + fmt(s.pm_ok / n, 1) + " | " + pct(s.pm_ok, s.pm) + " | " +
                        fmt(s.lines_cam / n, 0) + " / " + fmt(s.lines_q / n, 0) + " | " + fmt(s.lm / n, 1) + " | " +
                        fmt(s.lm_ok / n, 1) + " | " + pct(s.lm_ok, s.lm) + " | " +
                        fmt(s.pa ? s.pa_cands / s.pa : 0, 2) + " | " + pct(s.pa_any, s.pa) + " | " +
                        fmt(s.pa ? s.pa_pmass / s.pa : 0, 2) + " | " + fmt(s.la ? s.la_cands / s.la : 0, 2) + " | " +
                        pct(s.la_any, s.la) + " | " + fmt(s.la_cands ? s.la_planes / s.la_cands : 0, 2) + " |");
        }
    report.line("");
    if (lighterglue) reportLighterGlue(stats, lg_stats, times, b, report);
    report.line(
        "Timing per camera<->quasi pair (ms; budgets: points + lines <= 15 per image, matching <= 5 per pair, "
        "associations <= 2; classical):");
    report.line("");
    report.line("| stage | mean | max | n | budget |");
    report.line("|---|---|---|---|---|");
    for (const auto& [name, s] : times.stats())
        report.line("| " + name + " | " + fmt(s.mean(), 2) + " | " + fmt(s.max, 2) + " | " + std::to_string(s.n) +
                    " | " + budgetFor(name, s.mean()) + " |");
    report.line("");
}
}  // namespace quasiloc::bench
