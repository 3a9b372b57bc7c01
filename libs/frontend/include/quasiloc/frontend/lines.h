#pragma once
// Line segments and their hybrid descriptor (PAPER_NOTES: f_l = normalize([g_l * mean line-branch features;
// g_p * mean point-branch features]) along the segment).
//
// Options: [Lines] (LineOptions::declare, line_detector.cpp).
//
// Line branch (defined here for every front-end; the paper's learned line branch is not available): at every
// sample, the image gradient is read at 4 perpendicular offsets (-3/2, -1/2, +1/2, +3/2) * band_width_px and
// projected on the segment's normal n and direction d; per band the positive and negative parts of g.n and
// g.d are accumulated separately (as in MSLD/LBD): 4 bands x 4 = 16 values. The segment is oriented so that
// the image is brighter on the left of d (gradient polarity), making the descriptor independent of the
// endpoints' order. Point branch: the mean of the extractor's dense map (features.h) at the samples.
// Each branch mean is L2-normalised before weighting, so g_l and g_p set their shares exactly.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/frontend/features.h>
#include <string>
#include <vector>

namespace quasiloc::frontend
{
struct LineSegment
{
    Eigen::Vector2f p0{0, 0}, p1{0, 0};  ///< endpoints in pixels
    float length() const { return (p1 - p0).norm(); }
    Eigen::Vector2f direction() const { return (p1 - p0).normalized(); }
    Eigen::Vector2f midpoint() const { return 0.5f * (p0 + p1); }
    /** Homogeneous line l = p0 x p1 scaled so that l . (u, v, 1) is the signed distance in pixels. */
    Eigen::Vector3f homogeneous() const;
    /** Distance of a pixel to the infinite line. */
    float distanceToLine(const Eigen::Vector2f& p) const;
    /** Distance of a pixel to the segment. */
    float distanceToSegment(const Eigen::Vector2f& p) const;
};

enum class LineDetectorType
{
    Lsd,
    Fld,  ///< run with merging off
    EdLines
};

struct LineOptions : public core::DeclaredOptions
{
    LineDetectorType detector = LineDetectorType::Fld;
    double min_length_px = 25;
    int max_lines = 150;
    int samples_per_line = 16;
    double band_width_px = 2.0;
    double line_branch_weight = 1.0;
    double point_branch_weight = 1.0;

    void declare(core::OptionTable& t) override;
    /** InputError naming `input` and the key for a value out of its declared range, or both branch weights 0. */
    void check(const std::string& input) const;
};

class LineDetector
{
   public:
    explicit LineDetector(const LineOptions& options);
    ~LineDetector();
    LineDetector(const LineDetector&) = delete;
    LineDetector& operator=(const LineDetector&) = delete;
    /** Segments of an 8-bit grayscale image, length-filtered, at most max_lines (longest first). With a mask,
     *  segments whose midpoint falls outside it are dropped. */
    std::vector<LineSegment> detect(const cv::Mat& gray, const cv::Mat& mask = cv::Mat()) const;

   private:
    struct Impl;
    LineOptions options_;
    Impl* impl_;
};

/** Orients every segment so that the image is brighter on the left of p0 -> p1 (y down: left = (d.y, -d.x))
 *  and computes the hybrid descriptors: one L2-normalised CV_32F row per segment. `dense` may be empty (then
 *  the point branch is left out and the descriptor is the line branch alone). */
cv::Mat describeLines(const cv::Mat& gray, const DenseMap& dense, std::vector<LineSegment>& lines,
                      const LineOptions& options);

/** Working images of describeLines (the image gradients), kept by a caller that describes the lines of every
 *  frame: reusing them spares two image-sized allocations per call (see DenseMapScratch). */
struct LineDescriptorScratch
{
    cv::Mat gx, gy;
};

/** The same descriptors, with the gradients computed in `scratch`. */
cv::Mat describeLines(const cv::Mat& gray, const DenseMap& dense, std::vector<LineSegment>& lines,
                      const LineOptions& options, LineDescriptorScratch& scratch);

}  // namespace quasiloc::frontend
