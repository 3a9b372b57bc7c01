// The hybrid line descriptor (lines.h): line branch (banded gradient statistics along the segment) and point
// branch (the dense map averaged along it), each L2-normalised, weighted, concatenated, normalised.
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <quasiloc/frontend/lines.h>

namespace quasiloc::frontend
{
namespace
{
constexpr int kBands = 4;
constexpr int kLineDims = 4 * kBands;
constexpr float kBandOffsets[kBands] = {-1.5f, -0.5f, 0.5f, 1.5f};

Eigen::Vector2f sampleGradient(const cv::Mat& gx, const cv::Mat& gy, float x, float y)
{
    x = std::clamp(x, 0.f, float(gx.cols - 1.001f));
    y = std::clamp(y, 0.f, float(gx.rows - 1.001f));
    const int x0 = int(x), y0 = int(y);
    const float ax = x - x0, ay = y - y0;
    auto bil = [&](const cv::Mat& m) {
        const float* r0 = m.ptr<float>(y0);
        const float* r1 = m.ptr<float>(y0 + 1);
        return (1 - ay) * ((1 - ax) * r0[x0] + ax * r0[x0 + 1]) + ay * ((1 - ax) * r1[x0] + ax * r1[x0 + 1]);
    };
    return {bil(gx), bil(gy)};
}

void addNormalised(const float* v, int n, float weight, float* out)
{
    double n2 = 0;
    for (int i = 0; i < n; ++i) n2 += double(v[i]) * v[i];
    if (n2 <= 1e-20) return;
    const float s = weight / float(std::sqrt(n2));
    for (int i = 0; i < n; ++i) out[i] = v[i] * s;
}
}  // namespace

cv::Mat describeLines(const cv::Mat& gray, const DenseMap& dense, std::vector<LineSegment>& lines,
                      const LineOptions& options)
{
    LineDescriptorScratch scratch;
    return describeLines(gray, dense, lines, options, scratch);
}

cv::Mat describeLines(const cv::Mat& gray, const DenseMap& dense, std::vector<LineSegment>& lines,
                      const LineOptions& options, LineDescriptorScratch& scratch)
{
    const int P = dense.empty() ? 0 : dense.channels();
    cv::Mat desc = cv::Mat::zeros(int(lines.size()), kLineDims + P, CV_32F);
    if (lines.empty()) return desc;
    cv::Mat& gx = scratch.gx;
    cv::Mat& gy = scratch.gy;
    cv::Sobel(gray, gx, CV_32F, 1, 0, 3, 1.0 / 8.0);
    cv::Sobel(gray, gy, CV_32F, 0, 1, 3, 1.0 / 8.0);
    const int S = options.samples_per_line;
    const float bw = float(options.band_width_px);
    std::vector<float> line_sum(kLineDims), point_sum(P);
    for (size_t li = 0; li < lines.size(); ++li)
    {
        LineSegment& seg = lines[li];
        // Polarity: brighter on the left of d (left = (d.y, -d.x) with y down).
        {
            const Eigen::Vector2f d = seg.direction(), left(d.y(), -d.x());
            float g = 0;
            for (int s = 0; s < S; ++s)
            {
                const Eigen::Vector2f p = seg.p0 + (seg.p1 - seg.p0) * ((s + 0.5f) / S);
                g += sampleGradient(gx, gy, p.x(), p.y()).dot(left);
            }
            if (g < 0) std::swap(seg.p0, seg.p1);
        }
        const Eigen::Vector2f d = seg.direction(), left(d.y(), -d.x());
        std::fill(line_sum.begin(), line_sum.end(), 0.f);
        std::fill(point_sum.begin(), point_sum.end(), 0.f);
        for (int s = 0; s < S; ++s)
        {
            const Eigen::Vector2f p = seg.p0 + (seg.p1 - seg.p0) * ((s + 0.5f) / S);
            for (int b = 0; b < kBands; ++b)
            {
                const Eigen::Vector2f q = p + left * (kBandOffsets[b] * bw);
                const Eigen::Vector2f g = sampleGradient(gx, gy, q.x(), q.y());
                const float gn = g.dot(left), gd = g.dot(d);
                float* f = &line_sum[4 * b];
                f[0] += std::max(gn, 0.f), f[1] += std::max(-gn, 0.f), f[2] += std::max(gd, 0.f),
                    f[3] += std::max(-gd, 0.f);
            }
            if (P) dense.sampleAdd(p.x(), p.y(), 1.f, point_sum.data());
        }
        float* row = desc.ptr<float>(int(li));
        addNormalised(line_sum.data(), kLineDims, float(options.line_branch_weight), row);
        if (P) addNormalised(point_sum.data(), P, float(options.point_branch_weight), row + kLineDims);
        double n2 = 0;
        for (int c = 0; c < desc.cols; ++c) n2 += double(row[c]) * row[c];
        if (n2 > 0)
            for (int c = 0; c < desc.cols; ++c) row[c] = float(row[c] / std::sqrt(n2));
    }
    return desc;
}
}  // namespace quasiloc::frontend
