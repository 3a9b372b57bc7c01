// Part 2 of bench_frontend: the real EuRoC micro frames (V1_01_easy, first 95 stereo pairs, read with
// dataset::openEuroc). The MAV stands still on the ground during these frames, so a temporal match
// (I_{t-1}, I_t) is an inlier when its keypoint moved less than static_inlier_px (a temporal line match when its
// segments pass a gate of static_inlier_px / 2 deg). A stereo match is an inlier of a fundamental-matrix RANSAC
// (ransac_px) on the rectified keypoints. Per-stage times on 752x480 images give the budget table.
#include <opencv2/calib3d.hpp>
#include <quasiloc/dataset/frame_source.h>
#include <sys/stat.h>

#include "bench_common.h"

namespace quasiloc::bench
{
namespace
{
struct EurocStats
{
    double pairs = 0, kp = 0, lines = 0, tm = 0, tm_in = 0, tl = 0, tl_in = 0, sm = 0, sm_in = 0, sm_fit = 0;
};

size_t fundamentalInliers(const std::vector<cv::Point2f>& a, const std::vector<cv::Point2f>& b, double px)
{
    if (a.size() < 8) return 0;
    cv::Mat mask;
    const cv::Mat F = cv::findFundamentalMat(a, b, cv::FM_RANSAC, px, 0.999, mask);
    return F.empty() ? 0 : size_t(cv::countNonZero(mask));
}
}  // namespace

void runEuroc(const BenchOptions& b, const frontend::FrontendOptions& base, mrpt::system::CTimeLogger& logger,
              Report& report)
{
    auto src = dataset::openEuroc(b.euroc_dir);
    std::vector<dataset::StereoFrame> frames;
    dataset::StereoFrame f;
    while (int(frames.size()) < b.euroc_frames && src->next(f)) frames.push_back(f);
    StageTimes times(logger);
    std::map<std::string, EurocStats> stats;
    std::vector<std::string> types;
    for (const auto& t : b.extractorList())
    {
        struct stat st;
        if (t != "xfeat" || ::stat(withExtractor(base, t, b).features.xfeat_model_path.c_str(), &st) == 0)
            types.push_back(t);
    }
    for (const auto& type : types)
    {
        const frontend::FrontendOptions o = withExtractor(base, type, b);
        frontend::Frontend fe(o);
        frontend::StereoMatcher stereo(src->rig(), o.stereo);
        frontend::LineMatchingOptions static_gate = o.line_matching;
        static_gate.gate_max_distance_px = b.static_inlier_px, static_gate.gate_max_angle_deg = 2;
        EurocStats& s = stats[type];
        frontend::FrameFeatures prev;
        fe.extract(frames[0].left, cv::Mat(), prev);  // warm-up (first-call allocations), not timed
        for (size_t k = 0; k < frames.size(); ++k)
        {
            frontend::FrameFeatures left, right;
            Stopwatch sw_p;
            fe.extract(frames[k].left, cv::Mat(), left);
            const double ms_left = sw_p.ms();
            times.add(type + " points + lines per image", ms_left);
            fe.extract(frames[k].right, cv::Mat(), right);
            times.add(type + "   of which points", left.points_ms);
            times.add(type + "   of which lines (detect + describe)", left.lines_ms);
            s.kp += double(left.points.size()), s.lines += double(left.lines.size());

            Stopwatch sw_s;
            const auto sp = stereo.match(left.points, right.points);
            times.add(type + " stereo match + triangulation", sw_s.ms());
            std::vector<cv::Point2f> a, c;
            for (const auto& m : sp)
            {
                const Eigen::Vector2d l = stereo.rectifyPixel(0, left.points.keypoints[size_t(m.left)].pt);
                const Eigen::Vector2d r = stereo.rectifyPixel(1, right.points.keypoints[size_t(m.right)].pt);
                a.emplace_back(float(l.x()), float(l.y())), c.emplace_back(float(r.x()), float(r.y()));
            }
            s.sm += double(sp.size()), s.sm_in += double(fundamentalInliers(a, c, b.ransac_px));
            if (k > 0)
            {
                s.pairs += 1;
                Stopwatch sw_m;
                const auto pm = frontend::matchPoints(prev.points, left.points, o.point_matching);
                times.add(type + " match points (temporal)", sw_m.ms());
                Stopwatch sw_l;
                const auto lm = frontend::matchLines(prev.line_descriptors, prev.lines, left.line_descriptors,
                                                     left.lines, o.line_matching, false);
                times.add(type + " match lines (temporal)", sw_l.ms());
                s.tm += double(pm.size()), s.tl += double(lm.matches.size());
                for (const auto& m : pm)
                    s.tm_in += cv::norm(prev.points.keypoints[size_t(m.query)].pt -
                                        left.points.keypoints[size_t(m.train)].pt) < b.static_inlier_px;
                for (const auto& m : lm.matches)
                    s.tl_in +=
                        frontend::lineGate(prev.lines[size_t(m.query)], left.lines[size_t(m.train)], static_gate);
            }
            prev = std::move(left);
        }
    }

    report.line("## Real EuRoC micro frames (" + b.euroc_dir + ", " + std::to_string(frames.size()) + " stereo pairs)");
    report.line("");
    report.line("Temporal: consecutive left images, full-image search, inlier = moved < " + fmt(b.static_inlier_px, 1) +
                " px (static MAV). Stereo: epipolar search, inlier of a fundamental RANSAC at " + fmt(b.ransac_px, 1) +
                " px on rectified keypoints. Per-frame means.");
    report.line("");
    report.line(
        "| extractor | kp / image | lines / image | temporal point matches | inliers | temporal line matches | inliers "
        "| stereo matches | inliers |");
    report.line("|---|---|---|---|---|---|---|---|---|");
    for (const auto& type : types)
    {
        const EurocStats& s = stats[type];
        const double n = double(frames.size()), p = std::max(1.0, s.pairs);
        report.line("| " + type + " | " + fmt(s.kp / n, 0) + " | " + fmt(s.lines / n, 0) + " | " + fmt(s.tm / p, 1) +
                    " | " + pct(s.tm_in, s.tm) + " | " + fmt(s.tl / p, 1) + " | " + pct(s.tl_in, s.tl) + " | " +
                    fmt(s.sm / n, 1) + " | " + pct(s.sm_in, s.sm) + " |");
    }
    report.line("");
    report.line(
        "Timing on the real 752x480 frames (ms; budgets for classical extractors: points + lines <= 15 per image, "
        "matching <= 5 per pair):");
    report.line("");
    report.line("| stage | mean | max | n | budget |");
    report.line("|---|---|---|---|---|");
    for (const auto& [name, st] : times.stats())
    {
        report.line("| " + name + " | " + fmt(st.mean(), 2) + " | " + fmt(st.max, 2) + " | " + std::to_string(st.n) +
                    " | " + budgetFor(name, st.mean()) + " |");
    }
    report.line("");
}
}  // namespace quasiloc::bench
