#include <quasiloc/frontend/crossmodal_descriptors.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <quasiloc/core/error.h>
#include <utility>

namespace quasiloc::frontend
{
namespace
{
cv::Mat toFloat(const cv::Mat& image)
{
    core::require(!image.empty() && image.channels() == 1, "cross-modal descriptor input",
                  "expected a non-empty one-channel image");
    cv::Mat f;
    image.convertTo(f, CV_32F);
    return f;
}

cv::Mat blur(const cv::Mat& f, double sigma_px)
{
    if (sigma_px <= 0) return f.clone();
    cv::Mat out;
    cv::GaussianBlur(f, out, cv::Size(), sigma_px, sigma_px, cv::BORDER_REFLECT);
    return out;
}

/** Gaussian-weighted mean of `values` over the valid pixels, and the weight sum (0: no valid pixel near). */
void normalisedConvolution(const cv::Mat& values, const cv::Mat& valid01, double sigma_px, cv::Mat& mean,
                           cv::Mat& weight)
{
    cv::Mat num;
    cv::GaussianBlur(values.mul(valid01), num, cv::Size(), sigma_px, sigma_px, cv::BORDER_CONSTANT);
    cv::GaussianBlur(valid01, weight, cv::Size(), sigma_px, sigma_px, cv::BORDER_CONSTANT);
    mean = num / cv::max(weight, 1e-6f);
}

cv::Mat validMask01(const cv::Mat& valid, const cv::Size& size)
{
    core::require(valid.size() == size && valid.type() == CV_8UC1, "cross-modal descriptor mask",
                  "expected CV_8UC1 of the image's size");
    cv::Mat m;
    cv::Mat(valid != 0).convertTo(m, CV_32F, 1.0 / 255.0);
    return m;
}

std::vector<cv::Point> gridOffsets(int n, int step)
{
    std::vector<cv::Point> o;
    const int h = n / 2;
    for (int y = -h; y < n - h; ++y)
        for (int x = -h; x < n - h; ++x) o.emplace_back(x * step, y * step);
    return o;
}

/** Shifts f by (dx, dy): out(y, x) = f(y + dy, x + dx), replicating the border. */
cv::Mat shifted(const cv::Mat& f, int dx, int dy)
{
    cv::Mat padded, out;
    const int p = std::max(std::abs(dx), std::abs(dy));
    cv::copyMakeBorder(f, padded, p, p, p, p, cv::BORDER_REPLICATE);
    padded(cv::Rect(p + dx, p + dy, f.cols, f.rows)).copyTo(out);
    return out;
}

std::vector<cv::Mat> mindChannels(const cv::Mat& f, const CrossModalDescriptorOptions& o)
{
    const int r = o.mind_distance_px;
    // The four neighbours; the six pairs of MIND-SSC's 2D self-similarity context.
    const cv::Point n[4] = {{r, 0}, {0, r}, {-r, 0}, {0, -r}};
    const int pairs[6][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {0, 2}, {1, 3}};
    cv::Mat nb[4];
    for (int k = 0; k < 4; ++k) nb[k] = shifted(f, n[k].x, n[k].y);
    std::vector<cv::Mat> d(6);
    for (int k = 0; k < 6; ++k)
    {
        cv::Mat diff = nb[pairs[k][0]] - nb[pairs[k][1]];
        d[k] = blur(diff.mul(diff), o.mind_patch_sigma_px);
    }
    cv::Mat dmin = d[0].clone(), variance = cv::Mat::zeros(f.size(), CV_32F);
    for (const auto& dk : d) dmin = cv::min(dmin, dk), variance += dk;
    variance /= 6.0;
    const double mean_v = std::max(cv::mean(variance)[0], 1e-12);
    variance = cv::max(cv::min(variance, 1e3 * mean_v), 1e-3 * mean_v);
    for (auto& dk : d)
    {
        cv::Mat e = -(dk - dmin) / variance;
        cv::exp(e, dk);
    }
    return d;
}

std::vector<cv::Mat> orientationChannels(const cv::Mat& f, const CrossModalDescriptorOptions& o)
{
    cv::Mat gx, gy;
    cv::Sobel(f, gx, CV_32F, 1, 0, 3, 1.0, 0, cv::BORDER_REFLECT);
    cv::Sobel(f, gy, CV_32F, 0, 1, 3, 1.0, 0, cv::BORDER_REFLECT);
    cv::Mat mag2 = gx.mul(gx) + gy.mul(gy), rms;
    cv::sqrt(blur(mag2, o.orientation_norm_sigma_px), rms);
    const double floor = std::max(1e-6, 1e-3 * cv::mean(rms)[0]);
    const int B = o.orientation_bins;
    std::vector<cv::Mat> bins(static_cast<size_t>(B));
    for (auto& b : bins) b = cv::Mat::zeros(f.size(), CV_32F);
    for (int y = 0; y < f.rows; ++y)
    {
        const float *px = gx.ptr<float>(y), *py = gy.ptr<float>(y), *pr = rms.ptr<float>(y);
        for (int x = 0; x < f.cols; ++x)
        {
            const float m = std::sqrt(px[x] * px[x] + py[x] * py[x]);
            if (m <= 0) continue;
            const float w = m / float(std::max<double>(pr[x], floor));
            // Orientation modulo pi: the gradient and its negation fall in the same bin.
            float a = std::atan2(py[x], px[x]);
            if (a < 0) a += float(M_PI);
            if (a >= float(M_PI)) a -= float(M_PI);
            const float t = a / float(M_PI) * float(B) - 0.5f;
            const float t0 = std::floor(t);
            const int b0 = (int(t0) + B) % B, b1 = (b0 + 1) % B;
            const float frac = t - t0;
            bins[size_t(b0)].ptr<float>(y)[x] += w * (1 - frac);
            bins[size_t(b1)].ptr<float>(y)[x] += w * frac;
        }
    }
    const int c = o.orientation_cell_px;
    for (auto& b : bins) cv::boxFilter(b, b, CV_32F, cv::Size(c, c), cv::Point(-1, -1), false, cv::BORDER_REFLECT);
    return bins;
}
}  // namespace

std::string toString(DescriptorKind k)
{
    switch (k)
    {
        case DescriptorKind::Ncc: return "NCC";
        case DescriptorKind::Mind: return "MIND-SSC";
        case DescriptorKind::OrientationField: return "orientation field";
    }
    return "?";
}

cv::Mat locallyNormalised(const cv::Mat& gray, double sigma_px, double min_std)
{
    const cv::Mat f = toFloat(gray);
    const cv::Mat mean = blur(f, sigma_px);
    cv::Mat var = blur(f.mul(f), sigma_px) - mean.mul(mean), sd;
    cv::sqrt(cv::max(var, 0.0), sd);
    return (f - mean) / cv::max(sd, min_std);
}

cv::Mat rankEqualised(const cv::Mat& values, const cv::Mat& valid, const cv::Mat& depth, int depth_bands)
{
    const cv::Mat f = toFloat(values);
    validMask01(valid, f.size());
    const bool banded = depth_bands > 1 && !depth.empty();
    if (banded)
        core::require(depth.size() == f.size() && depth.type() == CV_32FC1, "rankEqualised depth",
                      "expected CV_32FC1 of the image's size");
    // Band of every valid pixel.
    std::vector<int> pixels;
    for (int y = 0; y < f.rows; ++y)
        for (int x = 0; x < f.cols; ++x)
            if (valid.at<uint8_t>(y, x) && (!banded || depth.at<float>(y, x) > 0)) pixels.push_back(y * f.cols + x);
    std::vector<int> band(pixels.size(), 0);
    if (banded && !pixels.empty())
    {
        float lo = std::numeric_limits<float>::max(), hi = 0;
        for (int p : pixels) lo = std::min(lo, depth.ptr<float>()[p]), hi = std::max(hi, depth.ptr<float>()[p]);
        const double llo = std::log(lo), width = std::max(1e-9, (std::log(hi) - llo) / depth_bands);
        for (size_t i = 0; i < pixels.size(); ++i)
            band[i] = std::min(depth_bands - 1, int((std::log(depth.ptr<float>()[pixels[i]]) - llo) / width));
    }
    cv::Mat out = cv::Mat::zeros(f.size(), CV_32F);
    const int nb = banded ? depth_bands : 1;
    for (int b = 0; b < nb; ++b)
    {
        // (value, pixel) pairs sort in contiguous memory: several times faster than indices compared through the
        // image (the tracker ranks a full-resolution quasi-image per keyframe).
        const float* v = f.ptr<float>();
        std::vector<std::pair<float, int>> in;
        for (size_t i = 0; i < pixels.size(); ++i)
            if (band[i] == b) in.emplace_back(v[pixels[i]], pixels[i]);
        if (in.empty()) continue;
        std::sort(in.begin(), in.end());
        const double scale = in.size() > 1 ? 1.0 / double(in.size() - 1) : 0.0;
        for (size_t i = 0; i < in.size();)
        {
            size_t j = i;
            while (j + 1 < in.size() && in[j + 1].first == in[i].first) ++j;
            const float rank = float(0.5 * double(i + j) * scale);
            for (size_t k = i; k <= j; ++k) out.ptr<float>()[in[k].second] = rank;
            i = j + 1;
        }
    }
    return out;
}

cv::Mat depthEdgeChannel(const cv::Mat& depth, const cv::Mat& valid, double sigma_px, double scale)
{
    core::require(depth.type() == CV_32FC1, "depthEdgeChannel", "expected a CV_32FC1 depth image");
    cv::Mat v = validMask01(valid, depth.size());
    v.setTo(0, depth <= 0);
    cv::Mat logd;
    cv::log(cv::max(depth, 1e-3f), logd);
    logd = logd.mul(v);
    cv::Mat mean, weight;
    normalisedConvolution(logd, v, sigma_px, mean, weight);
    cv::Mat out = (logd - mean) / scale;
    for (int y = 0; y < out.rows; ++y)
    {
        float* o = out.ptr<float>(y);
        const float* m = v.ptr<float>(y);
        for (int x = 0; x < out.cols; ++x) o[x] = m[x] > 0 ? std::tanh(o[x]) : 0.f;
    }
    return out;
}

cv::Mat fillInvalid(const cv::Mat& values, const cv::Mat& valid, double sigma_px)
{
    const cv::Mat f = toFloat(values);
    const cv::Mat v = validMask01(valid, f.size());
    cv::Mat mean, weight;
    normalisedConvolution(f, v, sigma_px, mean, weight);
    const double global = cv::countNonZero(valid) > 0 ? cv::mean(f, valid)[0] : 0.0;
    cv::Mat out = f.clone();
    for (int y = 0; y < f.rows; ++y)
        for (int x = 0; x < f.cols; ++x)
            if (!valid.at<uint8_t>(y, x))
                out.at<float>(y, x) = weight.at<float>(y, x) > 1e-3f ? mean.at<float>(y, x) : float(global);
    return out;
}

int DescriptorField::radius() const
{
    int r = 0;
    for (const auto& o : offsets) r = std::max({r, std::abs(o.x), std::abs(o.y)});
    return r;
}

bool DescriptorField::inside(int x, int y) const
{
    const int r = radius();
    const cv::Size s = size();
    return x >= r && y >= r && x < s.width - r && y < s.height - r;
}

bool DescriptorField::describe(int x, int y, float* out) const
{
    if (channels.empty() || !inside(x, y)) return false;
    const int n = dims(), C = int(channels.size());
    for (size_t k = 0; k < offsets.size(); ++k)
        for (int c = 0; c < C; ++c)
            out[int(k) * C + c] = channels[size_t(c)].at<float>(y + offsets[k].y, x + offsets[k].x);
    if (kind == DescriptorKind::Ncc)
    {
        double mean = 0;
        for (int i = 0; i < n; ++i) mean += out[i];
        mean /= n;
        for (int i = 0; i < n; ++i) out[i] -= float(mean);
    }
    auto normalise = [&]() {
        double s = 0;
        for (int i = 0; i < n; ++i) s += double(out[i]) * out[i];
        if (s < 1e-20) return false;
        const float inv = float(1.0 / std::sqrt(s));
        for (int i = 0; i < n; ++i) out[i] *= inv;
        return true;
    };
    if (!normalise()) return false;
    if (kind == DescriptorKind::OrientationField)
    {
        for (int i = 0; i < n; ++i) out[i] = std::min(out[i], float(clip));
        return normalise();
    }
    return true;
}

DescriptorField computeDescriptorField(const cv::Mat& image, DescriptorKind kind,
                                       const CrossModalDescriptorOptions& options)
{
    const cv::Mat f = blur(toFloat(image), options.smooth_sigma_px);
    DescriptorField d;
    d.kind = kind;
    d.clip = options.orientation_clip;
    switch (kind)
    {
        case DescriptorKind::Ncc:
            d.channels = {f};
            d.offsets = gridOffsets(2 * options.ncc_radius_px + 1, 1);
            break;
        case DescriptorKind::Mind:
            d.channels = mindChannels(f, options);
            d.offsets = gridOffsets(options.mind_grid, options.mind_step_px);
            break;
        case DescriptorKind::OrientationField:
        {
            d.channels = orientationChannels(f, options);
            // Cell centres: orientation_cells x orientation_cells cells of orientation_cell_px around the point.
            const int n = options.orientation_cells, c = options.orientation_cell_px;
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i)
                    d.offsets.emplace_back(int(std::lround((i - (n - 1) / 2.0) * c)),
                                           int(std::lround((j - (n - 1) / 2.0) * c)));
            break;
        }
    }
    return d;
}

float squaredDistance(const float* a, const float* b, int n)
{
    float s = 0;
    for (int i = 0; i < n; ++i)
    {
        const float d = a[i] - b[i];
        s += d * d;
    }
    return s;
}

}  // namespace quasiloc::frontend
