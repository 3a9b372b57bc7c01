// LSD (imgproc), FLD and EDLines (ximgproc) behind one call, with the length filter and the line budget.
#include <Eigen/Geometry>
#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc/edge_drawing.hpp>
#include <opencv2/ximgproc/fast_line_detector.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/core/ini_read.h>
#include <quasiloc/frontend/lines.h>

namespace quasiloc::frontend
{
Eigen::Vector3f LineSegment::homogeneous() const
{
    const Eigen::Vector3f l = Eigen::Vector3f(p0.x(), p0.y(), 1.f).cross(Eigen::Vector3f(p1.x(), p1.y(), 1.f));
    const float n = l.head<2>().norm();
    return n > 0 ? Eigen::Vector3f(l / n) : l;
}

float LineSegment::distanceToLine(const Eigen::Vector2f& p) const
{
    return std::abs(homogeneous().dot(Eigen::Vector3f(p.x(), p.y(), 1.f)));
}

float LineSegment::distanceToSegment(const Eigen::Vector2f& p) const
{
    const Eigen::Vector2f d = p1 - p0;
    const float len2 = d.squaredNorm();
    const float t = len2 > 0 ? std::clamp((p - p0).dot(d) / len2, 0.f, 1.f) : 0.f;
    return (p - (p0 + t * d)).norm();
}

void LineOptions::declare(core::OptionTable& t)
{
    using core::Range;
    t.addEnum("detector", detector,
              {{"lsd", LineDetectorType::Lsd}, {"fld", LineDetectorType::Fld}, {"edlines", LineDetectorType::EdLines}},
              "the line segment detector (FLD runs with merging off)");
    t.add("min_length_px", min_length_px, "px", Range::atLeast(2), "shorter segments are dropped");
    t.add("max_lines", max_lines, "", Range::atLeast(1), "the longest ones are kept");
    t.add("samples_per_line", samples_per_line, "", Range::between(2, 256),
          "descriptor samples spread evenly between the endpoints");
    t.add("band_width_px", band_width_px, "px", Range{0, 20, true, false},
          "line branch: perpendicular spacing of the sampling bands");
    t.add("line_branch_weight", line_branch_weight, "", Range::atLeast(0), "g_l: weight of the line branch");
    t.add("point_branch_weight", point_branch_weight, "", Range::atLeast(0), "g_p: weight of the point branch");
}

void LineOptions::check(const std::string& input) const
{
    checkRanges(input, "Lines");
    core::require(line_branch_weight + point_branch_weight > 0,
                  input + ": " + core::iniKeyName("Lines", "line_branch_weight"),
                  "line_branch_weight and point_branch_weight cannot both be 0");
}

struct LineDetector::Impl
{
    cv::Ptr<cv::LineSegmentDetector> lsd;
    cv::Ptr<cv::ximgproc::FastLineDetector> fld;
    cv::Ptr<cv::ximgproc::EdgeDrawing> ed;
};

LineDetector::LineDetector(const LineOptions& options) : options_(options), impl_(new Impl)
{
    options.check("line options");
    if (options.detector == LineDetectorType::Lsd)
        impl_->lsd = cv::createLineSegmentDetector(cv::LSD_REFINE_STD);
    else if (options.detector == LineDetectorType::Fld)
        impl_->fld = cv::ximgproc::createFastLineDetector(int(options.min_length_px), 1.414213562f, 50, 50, 3, false);
    else
    {
        impl_->ed = cv::ximgproc::createEdgeDrawing();
        cv::ximgproc::EdgeDrawing::Params p;
        p.MinLineLength = int(options.min_length_px);
        impl_->ed->setParams(p);
    }
}

LineDetector::~LineDetector() { delete impl_; }

std::vector<LineSegment> LineDetector::detect(const cv::Mat& gray, const cv::Mat& mask) const
{
    core::require(!gray.empty() && gray.type() == CV_8UC1, "line detection input",
                  "expected a non-empty 8-bit grayscale image (CV_8UC1)");
    std::vector<cv::Vec4f> raw;
    if (impl_->lsd)
        impl_->lsd->detect(gray, raw);
    else if (impl_->fld)
        impl_->fld->detect(gray, raw);
    else
    {
        impl_->ed->detectEdges(gray);
        impl_->ed->detectLines(raw);
    }
    std::vector<LineSegment> lines;
    for (const auto& v : raw)
    {
        LineSegment s{{v[0], v[1]}, {v[2], v[3]}};
        if (s.length() < options_.min_length_px) continue;
        if (!mask.empty())
        {
            const Eigen::Vector2f m = s.midpoint();
            const int x = std::clamp(int(m.x() + 0.5f), 0, mask.cols - 1),
                      y = std::clamp(int(m.y() + 0.5f), 0, mask.rows - 1);
            if (!mask.at<uchar>(y, x)) continue;
        }
        lines.push_back(s);
    }
    std::stable_sort(lines.begin(), lines.end(),
                     [](const LineSegment& a, const LineSegment& b) { return a.length() > b.length(); });
    if (int(lines.size()) > options_.max_lines) lines.resize(options_.max_lines);
    return lines;
}
}  // namespace quasiloc::frontend
