#pragma once
// The front-end as one object: every option section, and the per-image extraction (points, lines, hybrid line
// descriptors) that camera images and quasi-images share. Matching and association are free functions
// (point_matcher.h, line_matcher.h, association.h) because what differs between (I_{t-1}, I_t), (Q_t, I_t)
// and left-right pairs is only the search region and the gate.
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/system/CTimeLogger.h>

#include <memory>
#include <quasiloc/core/program_options.h>
#include <quasiloc/core/worker_thread.h>
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
    /** Wall time of the point extraction: keypoints, descriptors (and XFeat's dense map, a network output). */
    double points_ms = 0;
    /** Wall time of the line work: detection, the classical dense map (it feeds only the line descriptors; counted
     *  here whichever thread computed it), hybrid descriptors. */
    double lines_ms = 0;
    /** Wall time of the whole extraction: less than points_ms + lines_ms when the line detection ran
     *  concurrently with the points (Frontend::extract). */
    double total_ms = 0;
};

class Frontend
{
   public:
    /** InputError for bad options (or a missing XFeat model when type = xfeat). */
    explicit Frontend(const FrontendOptions& options);
    ~Frontend();

    /** Points and lines of an 8-bit grayscale image (mask optional: a quasi-image's `valid`). With more than one
     *  OpenCV thread (cv::getNumThreads()), the line detection runs on the Frontend's worker thread while the
     *  points are extracted, and the classical dense map in whichever of the two finishes first (frontend.cpp); the
     *  results are the same either way, and the same
     *  as calling the extractor, the detector and describeLines in turn. The stage times go into out.points_ms /
     *  out.lines_ms / out.total_ms and, if set, a CTimeLogger ("frontend.points", "frontend.lines",
     *  "frontend.extract"). Not reentrant: one Frontend per thread. */
    void extract(const cv::Mat& gray, const cv::Mat& mask, FrameFeatures& out);
    /** The point branch of extract() alone (points-only extraction): the same keypoints and descriptors (and
     *  XFeat's dense map), but no line detection, no classical dense map and no line descriptors (out.lines empty,
     *  out.lines_ms = 0). For callers that match points only, e.g. the tracker's stereo and temporal matching,
     *  which would otherwise pay for a line branch they drop. Runs on the calling thread; timed into
     *  "frontend.points" like extract(). Not reentrant (the extractor is shared with extract()). */
    void extractPoints(const cv::Mat& gray, const cv::Mat& mask, FrameFeatures& out);

    const FrontendOptions& options() const { return options_; }
    /** A program's stage logger (not owned; nullptr: none). */
    void setTimeLogger(mrpt::system::CTimeLogger* logger) { timer_ = logger; }

   private:
    FrontendOptions options_;
    std::unique_ptr<FeatureExtractor> extractor_;
    std::unique_ptr<LineDetector> line_detector_;
    bool dense_with_lines_ = false;  ///< the classical dense map is computed in the line branch (extract)
    // Working images reused from frame to frame (see DenseMapScratch).
    DenseMapScratch dense_scratch_;
    LineDescriptorScratch describe_scratch_;
    std::unique_ptr<core::WorkerThread>
        worker_;  ///< the thread of the line branch, started by the first concurrent extract
    mrpt::system::CTimeLogger* timer_ = nullptr;
};

}  // namespace quasiloc::frontend
