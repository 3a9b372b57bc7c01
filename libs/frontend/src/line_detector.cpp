// LSD (imgproc), FLD and EDLines (ximgproc) behind one call, with the length filter and the line budget.
#include <Eigen/Geometry>
#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc/edge_drawing.hpp>
#include <opencv2/ximgproc/fast_line_detector.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/frontend/lines.h>

#include "ini_read.h"

namespace quasiloc::frontend
{
using namespace detail;

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

void LineOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    detector = readString(cfg, s, "detector", detector);
    min_length_px = readDouble(cfg, s, "min_length_px", min_length_px);
    max_lines = readInt(cfg, s, "max_lines", max_lines);
    samples_per_line = readInt(cfg, s, "samples_per_line", samples_per_line);
    band_width_px = readDouble(cfg, s, "band_width_px", band_width_px);
    line_branch_weight = readDouble(cfg, s, "line_branch_weight", line_branch_weight);
    point_branch_weight = readDouble(cfg, s, "point_branch_weight", point_branch_weight);
}

void LineOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    c.write(s, "detector", detector, 30, 40, "lsd | fld | edlines");
    c.write(s, "min_length_px", min_length_px, 30, 40, "shorter segments are dropped");
    c.write(s, "max_lines", max_lines, 30, 40, "longest kept");
    c.write(s, "samples_per_line", samples_per_line, 30, 40, "descriptor samples along a segment");
    c.write(s, "band_width_px", band_width_px, 30, 40, "line-branch band spacing");
    c.write(s, "line_branch_weight", line_branch_weight, 30, 40, "g_l");
    c.write(s, "point_branch_weight", point_branch_weight, 30, 40, "g_p");
}

void LineOptions::check(const std::string& input) const
{
    const std::string S = "Lines";
    requireKey(detector == "lsd" || detector == "fld" || detector == "edlines", input, S, "detector",
               "'" + detector + "' is not one of lsd, fld, edlines");
    requireKey(min_length_px >= 2, input, S, "min_length_px", "must be >= 2");
    requireKey(max_lines >= 1, input, S, "max_lines", "must be >= 1");
    requireKey(samples_per_line >= 2 && samples_per_line <= 256, input, S, "samples_per_line", "must be in [2, 256]");
    requireKey(band_width_px > 0 && band_width_px <= 20, input, S, "band_width_px", "must be in (0, 20]");
    requireKey(line_branch_weight >= 0, input, S, "line_branch_weight", "must be >= 0");
    requireKey(point_branch_weight >= 0, input, S, "point_branch_weight", "must be >= 0");
    requireKey(line_branch_weight + point_branch_weight > 0, input, S, "line_branch_weight",
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
    if (options.detector == "lsd") impl_->lsd = cv::createLineSegmentDetector(cv::LSD_REFINE_STD);
    else if (options.detector == "fld")
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
    if (impl_->lsd) impl_->lsd->detect(gray, raw);
    else if (impl_->fld) impl_->fld->detect(gray, raw);
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
            const int x = std::clamp(int(m.x() + 0.5f), 0, mask.cols - 1), y = std::clamp(int(m.y() + 0.5f), 0, mask.rows - 1);
            if (!mask.at<uchar>(y, x)) continue;
        }
        lines.push_back(s);
    }
    std::stable_sort(lines.begin(), lines.end(), [](const LineSegment& a, const LineSegment& b) { return a.length() > b.length(); });
    if (int(lines.size()) > options_.max_lines) lines.resize(options_.max_lines);
    return lines;
}
}  // namespace quasiloc::frontend
