// Encoding of completed depth and reflectivity: H = h(I), S = s0, V = b1 + b2 * h(F(D)).
#include <algorithm>
#include <cmath>

#include "render_stages.h"

namespace quasiloc::quasi::detail
{
HueTable HueTable::make(const QuasiOptions& o)
{
    HueTable t;
    const double s = o.saturation;
    for (int l = 0; l < 256; ++l)
    {
        // HSV -> RGB at V = 1. RGB is linear in V for a fixed (H, S), so the encoder scales this entry by V.
        double hue = o.hue_low_deg + (o.hue_high_deg - o.hue_low_deg) * l / 255.0;
        hue = std::fmod(hue, 360.0);
        const double hp = hue / 60.0;
        const double c = s, xx = c * (1 - std::abs(std::fmod(hp, 2.0) - 1)), m = 1 - c;
        double r = 0, g = 0, b = 0;
        switch (std::min(5, int(hp)))
        {
            case 0: r = c, g = xx; break;
            case 1: r = xx, g = c; break;
            case 2: g = c, b = xx; break;
            case 3: g = xx, b = c; break;
            case 4: r = xx, b = c; break;
            default: r = c, b = xx; break;
        }
        t.bgr[l][0] = float(b + m);
        t.bgr[l][1] = float(g + m);
        t.bgr[l][2] = float(r + m);
        t.luminance[l] = float(0.299 * (r + m) + 0.587 * (g + m) + 0.114 * (b + m));
    }
    return t;
}

void reflectivityPercentiles(const std::vector<uint32_t>& histogram, const QuasiOptions& o, float& lo, float& hi)
{
    uint64_t total = 0;
    for (uint32_t c : histogram) total += c;
    lo = 0, hi = 1;
    if (total == 0) return;
    auto percentile = [&](double pct) {
        const double target = pct / 100.0 * double(total);
        uint64_t cum = 0;
        for (size_t b = 0; b < histogram.size(); ++b)
        {
            cum += histogram[b];
            if (double(cum) >= target && cum > 0) return float((b + 0.5) / histogram.size());
        }
        return 1.0f;
    };
    lo = percentile(o.reflectivity_percentile_low);
    hi = percentile(o.reflectivity_percentile_high);
    // A uniform reflectivity gives no contrast to stretch: keep a non-zero span (all pixels get one hue).
    if (hi - lo < 1.0f / histogram.size()) hi = lo + 1.0f / histogram.size();
}

namespace
{
/** F(D) at (x, y), relative to the pixel's depth; invalid neighbours are ignored. */
inline float depthVariation(const float* up, const float* mid, const float* down, const uint8_t* vup,
                            const uint8_t* vmid, const uint8_t* vdown, int x, int width, bool laplacian)
{
    const float d = mid[x];
    const bool l = x > 0 && vmid[x - 1], r = x + 1 < width && vmid[x + 1];
    const bool u = vup && vup[x], b = vdown && vdown[x];
    float f = 0;
    if (laplacian)
    {
        if (l && r) f = std::max(f, std::abs(mid[x - 1] + mid[x + 1] - 2 * d));
        if (u && b) f = std::max(f, std::abs(up[x] + down[x] - 2 * d));
    }
    else
    {
        if (l) f = std::max(f, std::abs(mid[x - 1] - d));
        if (r) f = std::max(f, std::abs(mid[x + 1] - d));
        if (u) f = std::max(f, std::abs(up[x] - d));
        if (b) f = std::max(f, std::abs(down[x] - d));
    }
    return f / d;
}
}  // namespace

void encodeRows(QuasiImage& q, int y0, int y1, float refl_lo, float refl_hi, const HueTable& hue,
                const QuasiOptions& o)
{
    const int width = q.depth.cols, height = q.depth.rows;
    const bool laplacian = o.edgeOperator() == EdgeOperator::Laplacian;
    const GrayMode gray_mode = o.grayMode();
    const float inv_span = 1.0f / (refl_hi - refl_lo);
    const float inv_edge = float(1.0 / o.edge_scale_rel);
    const float b1 = float(o.value_base), b2 = float(o.value_gain);
    for (int y = y0; y < y1; ++y)
    {
        const float* mid = q.depth.ptr<float>(y);
        const float* up = y > 0 ? q.depth.ptr<float>(y - 1) : nullptr;
        const float* down = y + 1 < height ? q.depth.ptr<float>(y + 1) : nullptr;
        const uint8_t* vmid = q.valid.ptr<uint8_t>(y);
        const uint8_t* vup = y > 0 ? q.valid.ptr<uint8_t>(y - 1) : nullptr;
        const uint8_t* vdown = y + 1 < height ? q.valid.ptr<uint8_t>(y + 1) : nullptr;
        const float* refl = q.reflectivity.ptr<float>(y);
        uint8_t* bgr = q.bgr.ptr<uint8_t>(y);
        uint8_t* gray = q.gray.ptr<uint8_t>(y);
        for (int x = 0; x < width; ++x)
        {
            if (!vmid[x])
            {
                bgr[3 * x] = bgr[3 * x + 1] = bgr[3 * x + 2] = 0;
                gray[x] = 0;
                continue;
            }
            const float hI = std::clamp((refl[x] - refl_lo) * inv_span, 0.0f, 1.0f);
            const int level = int(hI * 255.0f + 0.5f);
            const float F = depthVariation(up, mid, down, vup, vmid, vdown, x, width, laplacian);
            const float V = b1 + b2 * std::min(1.0f, F * inv_edge);
            const float scale = 255.0f * V;
            bgr[3 * x] = uint8_t(hue.bgr[level][0] * scale + 0.5f);
            bgr[3 * x + 1] = uint8_t(hue.bgr[level][1] * scale + 0.5f);
            bgr[3 * x + 2] = uint8_t(hue.bgr[level][2] * scale + 0.5f);
            float g = 0;
            switch (gray_mode)
            {
                case GrayMode::Luminance: g = hue.luminance[level] * scale; break;
                case GrayMode::Value: g = scale; break;
                case GrayMode::ShadedReflectivity: g = (0.25f + 0.75f * hI) * scale; break;
            }
            gray[x] = uint8_t(std::min(255.0f, g + 0.5f));
        }
    }
}

}  // namespace quasiloc::quasi::detail
