#pragma once
// The front-end as one object: every option section, and the per-image extraction (points, lines, hybrid line
// descriptors) that camera images and quasi-images share. Matching and association are free functions
// (point_matcher.h, line_matcher.h, association.h) because what differs between (I_{t-1}, I_t), (Q_t, I_t)
// and left-right pairs is only the search region and the gate.
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/system/CTimeLogger.h>

#include <memory>
#include <quasiloc/core/program_options.h>
#include <quasiloc/frontend/association.h>
#include <quasiloc/frontend/features.h>
#include <quasiloc/frontend/line_matcher.h>
#include <quasiloc/frontend/lines.h>
#include <quasiloc/frontend/point_matcher.h>
#include <quasiloc/frontend/stereo_matcher.h>
#include <string>
#include <vector>

namespace quasiloc::frontend
{
struct FrontendOptions
{
    FeatureOptions features;
    PointMatchingOptions point_matching;
    LineOptions lines;
    LineMatchingOptions line_matching;
    AssociationOptions association;
    StereoOptions stereo;

    /** Loads the sections [Features], [PointMatching], [Lines], [LineMatching], [Association], [Stereo]
     *  (absent sections keep the defaults; unknown keys are InputErrors) and checks every value. */
    void load(const mrpt::config::CConfigFileBase& cfg, const std::string& config_name);
    void check(const std::string& input) const;
    /** The sections for core::writeEffectiveConfig. */
    std::vector<core::OptionsSection> sections() const;
};

struct FrameFeatures
{
    Features points;
    std::vector<LineSegment> lines;
    cv::Mat line_descriptors;  ///< one CV_32F row per line
    double points_ms = 0;      ///< wall time of the point extraction (keypoints, descriptors, dense map)
    double lines_ms = 0;       ///< wall time of line detection + hybrid descriptors
};

class Frontend
{
   public:
    /** InputError for bad options (or a missing XFeat model when type = xfeat). */
    explicit Frontend(const FrontendOptions& options);
    ~Frontend();

    /** Points and lines of an 8-bit grayscale image (mask optional: a quasi-image's `valid`). The stage times
     *  go into out.points_ms / out.lines_ms and, if set, a CTimeLogger ("frontend.points", "frontend.lines"). */
    void extract(const cv::Mat& gray, const cv::Mat& mask, FrameFeatures& out);

    const FrontendOptions& options() const { return options_; }
    /** A program's stage logger (not owned; nullptr: none). */
    void setTimeLogger(mrpt::system::CTimeLogger* logger) { timer_ = logger; }

   private:
    FrontendOptions options_;
    std::unique_ptr<FeatureExtractor> extractor_;
    std::unique_ptr<LineDetector> line_detector_;
    mrpt::system::CTimeLogger* timer_ = nullptr;
};

}  // namespace quasiloc::frontend
