// Dense maps sampled by the hybrid line descriptor (point branch), see features.h.
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <quasiloc/frontend/features.h>

namespace quasiloc::frontend
{
void DenseMap::sampleAdd(float x, float y, float weight, float* out) const
{
    if (data.empty()) return;
    const float gx = std::clamp(float((x - offset) / stride), 0.f, float(cols_cells - 1));
    const float gy = std::clamp(float((y - offset) / stride), 0.f, float(rows_cells - 1));
    const int x0 = std::min(int(gx), cols_cells - 1), y0 = std::min(int(gy), rows_cells - 1);
    const int x1 = std::min(x0 + 1, cols_cells - 1), y1 = std::min(y0 + 1, rows_cells - 1);
    const float ax = gx - float(x0), ay = gy - float(y0);
    const float w[4] = {(1 - ax) * (1 - ay) * weight, ax * (1 - ay) * weight, (1 - ax) * ay * weight, ax * ay * weight};
    const int rows[4] = {y0 * cols_cells + x0, y0 * cols_cells + x1, y1 * cols_cells + x0, y1 * cols_cells + x1};
    const int C = data.cols;
    for (int k = 0; k < 4; ++k)
    {
        if (w[k] == 0.f) continue;
        const float* v = data.ptr<float>(rows[k]);
        for (int c = 0; c < C; ++c) out[c] += w[k] * v[c];
    }
}

DenseMap computeGradientDenseMap(const cv::Mat& gray, DenseMapScratch& scratch)
{
    constexpr int kBins = 8;
    constexpr double kSigmas[2] = {1.0, 2.0};
    cv::Mat& half = scratch.half;
    cv::resize(gray, scratch.half_u8, cv::Size(gray.cols / 4, gray.rows / 4), 0, 0, cv::INTER_AREA);
    scratch.half_u8.convertTo(half, CV_32F, 1.0 / 255.0);
    cv::Sobel(half, scratch.gx, CV_32F, 1, 0, 3);
    cv::Sobel(half, scratch.gy, CV_32F, 0, 1, 3);
    const int H = half.rows, W = half.cols;
    auto& bins = scratch.bins;
    bins.resize(kBins);
    for (auto& b : bins)
    {
        b.create(H, W, CV_32F);
        b.setTo(0);
    }
    // Unsigned orientation (mod pi): camera images and quasi-images often disagree on the polarity of an edge.
    for (int y = 0; y < H; ++y)
    {
        const float* px = scratch.gx.ptr<float>(y);
        const float* py = scratch.gy.ptr<float>(y);
        for (int x = 0; x < W; ++x)
        {
            const float mag = std::sqrt(px[x] * px[x] + py[x] * py[x]);
            if (mag < 1e-4f) continue;
            float a = std::atan2(py[x], px[x]);
            if (a < 0) a += float(M_PI);
            const float f = a / float(M_PI) * kBins;
            const int b0 = int(f) % kBins, b1 = (b0 + 1) % kBins;
            const float t = f - std::floor(f);
            bins[b0].at<float>(y, x) += (1 - t) * mag;
            bins[b1].at<float>(y, x) += t * mag;
        }
    }
    // Pooled channels straight into the cell-major output (channel = sigma index * kBins + bin).
    DenseMap m;
    m.data.create(H * W, 2 * kBins, CV_32F);
    for (int si = 0; si < 2; ++si)
        for (int b = 0; b < kBins; ++b)
        {
            cv::GaussianBlur(bins[size_t(b)], scratch.pooled, cv::Size(0, 0), kSigmas[si], kSigmas[si],
                             cv::BORDER_REFLECT);
            const int ch = si * kBins + b;
            for (int y = 0; y < H; ++y)
            {
                const float* src = scratch.pooled.ptr<float>(y);
                for (int x = 0; x < W; ++x) m.data.ptr<float>(y * W + x)[ch] = src[x];
            }
        }
    m.cols_cells = W;
    m.rows_cells = H;
    m.stride = double(gray.cols) / W;
    m.offset = 0.5 * m.stride - 0.5;
    for (int r = 0; r < m.data.rows; ++r)
    {
        float* v = m.data.ptr<float>(r);
        double n2 = 0;
        for (int c = 0; c < m.data.cols; ++c) n2 += double(v[c]) * v[c];
        if (n2 < 1e-12) continue;
        const float inv = float(1.0 / std::sqrt(n2));
        for (int c = 0; c < m.data.cols; ++c) v[c] *= inv;
    }
    return m;
}

DenseMap computeGradientDenseMap(const cv::Mat& gray)
{
    DenseMapScratch scratch;
    return computeGradientDenseMap(gray, scratch);
}
}  // namespace quasiloc::frontend
