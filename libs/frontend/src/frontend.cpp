#include <chrono>
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
    line_matching.check(input);
    association.check(input);
    stereo.check(input);
}

std::vector<core::OptionsSection> FrontendOptions::sections() const
{
    return {{"Features", &features},           {"PointMatching", &point_matching}, {"Lines", &lines},
            {"LineMatching", &line_matching}, {"Association", &association},     {"Stereo", &stereo}};
}

Frontend::Frontend(const FrontendOptions& options)
    : options_(options),
      extractor_(createFeatureExtractor(options.features)),
      line_detector_(std::make_unique<LineDetector>(options.lines))
{
    options.check("front-end options");
}

Frontend::~Frontend() = default;

void Frontend::extract(const cv::Mat& gray, const cv::Mat& mask, FrameFeatures& out)
{
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    extractor_->extract(gray, mask, out.points);
    const auto t1 = clock::now();
    out.lines = line_detector_->detect(gray, mask);
    out.line_descriptors = describeLines(gray, out.points.dense, out.lines, options_.lines);
    const auto t2 = clock::now();
    out.points_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
    out.lines_ms = std::chrono::duration<double, std::milli>(t2 - t1).count();
    if (timer_)
    {
        timer_->registerUserMeasure("frontend.points", out.points_ms * 1e-3, true);
        timer_->registerUserMeasure("frontend.lines", out.lines_ms * 1e-3, true);
    }
}
}  // namespace quasiloc::frontend
