#include <atomic>
#include <chrono>
#include <exception>
#include <functional>
#include <opencv2/core/utility.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/frontend/frontend.h>

namespace quasiloc::frontend
{
void FrontendOptions::load(const mrpt::config::CConfigFileBase& cfg, const std::string& config_name)
{
    core::loadOptionsChecked(features, cfg, "Features", config_name);
    core::loadOptionsChecked(point_matching, cfg, "PointMatching", config_name);
    core::loadOptionsChecked(lines, cfg, "Lines", config_name);
    core::loadOptionsChecked(line_matching, cfg, "LineMatching", config_name);
    core::loadOptionsChecked(association, cfg, "Association", config_name);
    core::loadOptionsChecked(stereo, cfg, "Stereo", config_name);
    check(config_name);
}

void FrontendOptions::check(const std::string& input) const
{
    features.check(input);
    point_matching.check(input);
    lines.check(input);
    line_matching.checkRanges(input, "LineMatching");
    association.checkRanges(input, "Association");
    stereo.check(input);
    if (point_matching.useLighterGlue())
        core::require(
            features.type == FeatureType::XFeat, input + ": [PointMatching] method",
            "lighterglue matches XFeat descriptors: it needs [Features] type = xfeat, not " + toString(features.type));
}

std::vector<core::OptionsSection> FrontendOptions::sections() const
{
    return {{"Features", &features},          {"PointMatching", &point_matching}, {"Lines", &lines},
            {"LineMatching", &line_matching}, {"Association", &association},      {"Stereo", &stereo}};
}

namespace
{
/** The classical dense map depends on the image alone and feeds only the hybrid line descriptors: the front-end
 *  computes it itself, in whichever branch of extract() finishes first, rather than in the point extractor. XFeat's
 *  dense map is an output of its network: it stays with the points. */
bool denseMapWithLines(const FeatureOptions& f) { return f.dense_map && f.type != FeatureType::XFeat; }

FeatureOptions pointExtractorOptions(FeatureOptions f)
{
    if (denseMapWithLines(f)) f.dense_map = false;
    return f;
}
}  // namespace

Frontend::Frontend(const FrontendOptions& options)
    : options_(options),
      extractor_(createFeatureExtractor(pointExtractorOptions(options.features))),
      line_detector_(std::make_unique<LineDetector>(options.lines)),
      dense_with_lines_(denseMapWithLines(options.features))
{
    options.check("front-end options");
}

Frontend::~Frontend() = default;

void Frontend::extract(const cv::Mat& gray, const cv::Mat& mask, FrameFeatures& out)
{
    using clock = std::chrono::steady_clock;
    auto ms = [](clock::time_point a, clock::time_point b) {
        return std::chrono::duration<double, std::milli>(b - a).count();
    };
    const auto t0 = clock::now();
    // Two independent branches: the points (keypoints, descriptors; XFeat's dense map) and the lines (detection).
    // Neither keeps two cores busy for long (ORB, FAST, FLD and the dense map are mostly single-threaded), so with a
    // second core the line branch runs on the worker thread meanwhile. A thread of our own, not a cv::parallel_for_
    // region, so that the extractors that use OpenCV's pool themselves (SIFT, AKAZE, the XFeat network) keep it. With
    // cv::setNumThreads(1) (or 0) everything runs on the calling thread, points first.
    // The classical dense map (~2.5 ms per 752x480 image) is computed by whichever branch finishes first: a fixed
    // place would lengthen the longer branch whenever the two are close (ORB and FLD on a quasi-image take about
    // the same time), and which one is longer depends on the extractor, the image and the load of the machine.
    // The map is the same whichever thread computes it.
    DenseMap dense;
    double dense_ms = 0;
    std::atomic<bool> dense_taken{!dense_with_lines_};
    auto dense_if_first = [&] {
        if (dense_taken.exchange(true)) return;
        const auto t = clock::now();
        dense = computeGradientDenseMap(gray, dense_scratch_);
        dense_ms = ms(t, clock::now());
    };
    std::vector<LineSegment> lines;
    double detect_ms = 0;
    auto line_branch = [&] {
        const auto t = clock::now();
        lines = line_detector_->detect(gray, mask);
        detect_ms = ms(t, clock::now());
        dense_if_first();
    };
    const bool concurrent = cv::getNumThreads() > 1;
    if (concurrent && !worker_) worker_ = std::make_unique<core::WorkerThread>();
    if (concurrent) worker_->start(line_branch);
    double points_ms = 0;
    try
    {
        extractor_->extract(gray, mask, out.points);
        points_ms = ms(t0, clock::now());
        dense_if_first();
    }
    catch (...)
    {
        if (concurrent) worker_->waitForError();  // the line branch uses this frame's locals: let it finish first
        throw;
    }
    if (!concurrent)
        line_branch();
    else
        worker_->wait();
    out.lines = std::move(lines);
    if (dense_with_lines_) out.points.dense = std::move(dense);
    // The hybrid descriptors sample the dense map: after both branches.
    const auto t_describe = clock::now();
    out.line_descriptors = describeLines(gray, out.points.dense, out.lines, options_.lines, describe_scratch_);
    const auto t_end = clock::now();
    out.points_ms = points_ms;
    // The classical dense map counts as line work wherever it ran: it feeds only the line descriptors.
    out.lines_ms = detect_ms + (dense_with_lines_ ? dense_ms : 0) + ms(t_describe, t_end);
    out.total_ms = ms(t0, t_end);
    if (timer_)
    {
        timer_->registerUserMeasure("frontend.points", out.points_ms * 1e-3, true);
        timer_->registerUserMeasure("frontend.lines", out.lines_ms * 1e-3, true);
        timer_->registerUserMeasure("frontend.extract", out.total_ms * 1e-3, true);
    }
}

void Frontend::extractPoints(const cv::Mat& gray, const cv::Mat& mask, FrameFeatures& out)
{
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    extractor_->extract(gray, mask, out.points);
    out.lines.clear();
    out.line_descriptors = cv::Mat();
    out.points_ms = out.total_ms = std::chrono::duration<double, std::milli>(clock::now() - t0).count();
    out.lines_ms = 0;
    if (timer_) timer_->registerUserMeasure("frontend.points", out.points_ms * 1e-3, true);
}
}  // namespace quasiloc::frontend
