// Encoding of completed depth and reflectivity: H = h(I), S = s0, V = b1 + b2 * h(F(D)).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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
        for (int c = 0; c < 3; ++c) t.bgrl[l][c] = t.bgr[l][c];
        t.bgrl[l][3] = t.luminance[l];
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
/** Histogram bins of a row's reflectivities (vectorised). */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
void reflectivityBins(const float* __restrict refl, int width, int32_t* __restrict bin)
{
    for (int x = 0; x < width; ++x)
        bin[x] = std::min(kReflHistogramBins - 1, std::max(0, int(refl[x] * kReflHistogramBins)));
}
}  // namespace

size_t reflectivityHistogramRows(const QuasiImage& q, int y0, int y1, std::vector<uint32_t>& histogram)
{
    const int width = q.reflectivity.cols;
    // Four interleaved histograms: neighbouring pixels often share a bin, and one histogram would chain every
    // increment on the previous one through memory. Invalid pixels add 0 (no branch).
    std::vector<uint32_t> h4(4 * kReflHistogramBins, 0);
    std::vector<int32_t> bin(width);
    size_t sparse_count = 0;
    for (int y = y0; y < y1; ++y)
    {
        const uint8_t* v = q.valid.ptr<uint8_t>(y);
        const uint8_t* sp = q.sparse.ptr<uint8_t>(y);
        reflectivityBins(q.reflectivity.ptr<float>(y), width, bin.data());
        for (int x = 0; x < width; ++x) h4[(x & 3) * kReflHistogramBins + bin[x]] += v[x] != 0;
        for (int x = 0; x < width; ++x) sparse_count += sp[x] != 0;
    }
    histogram.assign(kReflHistogramBins, 0);
    for (int i = 0; i < kReflHistogramBins; ++i)
    {
        const uint32_t* h = h4.data() + i;
        histogram[i] = h[0] + h[kReflHistogramBins] + h[2 * kReflHistogramBins] + h[3 * kReflHistogramBins];
    }
    return sparse_count;
}

namespace
{
/** F(D) of one pixel relative to its depth d; the neighbours' depths and validity (l, r, u, b) given. */
template <bool Laplacian>
inline float depthVariation(float d, float dl, float dr, float du, float db, bool l, bool r, bool u, bool b)
{
    if (Laplacian)
    {
        const float fx = (l & r) ? std::abs(dl + dr - 2 * d) : 0.0f;
        const float fy = (u & b) ? std::abs(du + db - 2 * d) : 0.0f;
        return std::max(fx, fy) / d;
    }
    const float fl = l ? std::abs(dl - d) : 0.0f, fr = r ? std::abs(dr - d) : 0.0f;
    const float fu = u ? std::abs(du - d) : 0.0f, fb = b ? std::abs(db - d) : 0.0f;
    return std::max(std::max(fl, fr), std::max(fu, fb)) / d;
}

struct EncodeParams
{
    float refl_lo, inv_span, inv_edge, b1, b2;
};

/** Pixels [x0, x1) of a row: the level of h(I) and 255 * V (0 where invalid, so that the colour loop needs no
 *  test) from F(D) (invalid neighbours ignored). Branch-free, so that the compiler vectorises it; the same
 *  float operations as the per-pixel rule. The caller makes x0 - 1 and x1 readable; `up`/`down` (and their
 *  masks) are an invalid row at the image border. */
template <bool Laplacian>
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
void levelsAndScales(const float* __restrict up, const float* __restrict mid, const float* __restrict down,
                     const uint8_t* __restrict vup, const uint8_t* __restrict vmid, const uint8_t* __restrict vdown,
                     const float* __restrict refl, int x0, int x1, EncodeParams p, int32_t* __restrict level,
                     float* __restrict scale, float* __restrict hI_out)
{
    for (int x = x0; x < x1; ++x)
    {
        const float F = depthVariation<Laplacian>(mid[x], mid[x - 1], mid[x + 1], up[x], down[x], vmid[x - 1] != 0,
                                                  vmid[x + 1] != 0, vup[x] != 0, vdown[x] != 0);
        const float V = p.b1 + p.b2 * std::min(1.0f, F * p.inv_edge);
        const float hI = std::clamp((refl[x] - p.refl_lo) * p.inv_span, 0.0f, 1.0f);
        const bool valid = vmid[x] != 0;
        level[x] = valid ? int32_t(hI * 255.0f + 0.5f) : 0;
        scale[x] = valid ? 255.0f * V : 0.0f;
        hI_out[x] = hI;
    }
}

/** The first and last pixel of a row (a neighbour beyond the row end is invalid). */
template <bool Laplacian>
void levelAndScaleAt(const float* up, const float* mid, const float* down, const uint8_t* vup, const uint8_t* vmid,
                     const uint8_t* vdown, const float* refl, int x, int width, EncodeParams p, int32_t* level,
                     float* scale, float* hI_out)
{
    const bool l = x > 0 && vmid[x - 1], r = x + 1 < width && vmid[x + 1];
    const float F = depthVariation<Laplacian>(mid[x], l ? mid[x - 1] : 0.0f, r ? mid[x + 1] : 0.0f, up[x], down[x], l,
                                              r, vup[x] != 0, vdown[x] != 0);
    const float V = p.b1 + p.b2 * std::min(1.0f, F * p.inv_edge);
    const float hI = std::clamp((refl[x] - p.refl_lo) * p.inv_span, 0.0f, 1.0f);
    const bool valid = vmid[x] != 0;
    level[x] = valid ? int32_t(hI * 255.0f + 0.5f) : 0;
    scale[x] = valid ? 255.0f * V : 0.0f;
    hI_out[x] = hI;
}

template <bool Laplacian>
void levelsAndScalesRow(const float* up, const float* mid, const float* down, const uint8_t* vup, const uint8_t* vmid,
                        const uint8_t* vdown, const float* refl, int width, EncodeParams p, int32_t* level,
                        float* scale, float* hI)
{
    levelAndScaleAt<Laplacian>(up, mid, down, vup, vmid, vdown, refl, 0, width, p, level, scale, hI);
    if (width > 2) levelsAndScales<Laplacian>(up, mid, down, vup, vmid, vdown, refl, 1, width - 1, p, level, scale, hI);
    if (width > 1)
        levelAndScaleAt<Laplacian>(up, mid, down, vup, vmid, vdown, refl, width - 1, width, p, level, scale, hI);
}
}  // namespace

void encodeRows(QuasiImage& q, int y0, int y1, float refl_lo, float refl_hi, const HueTable& hue, const QuasiOptions& o)
{
    const int width = q.depth.cols, height = q.depth.rows;
    const bool laplacian = o.edge_operator == EdgeOperator::Laplacian;
    const GrayMode gray_mode = o.gray_mode;
    const EncodeParams p{refl_lo, 1.0f / (refl_hi - refl_lo), float(1.0 / o.edge_scale_rel), float(o.value_base),
                         float(o.value_gain)};
    // Row scratch (image-width, per call): levels, scales, h(I), and an all-invalid row for the borders.
    std::vector<int32_t> level(width);
    std::vector<float> scale(width), hI(width), zero_depth(width, 0.0f);
    std::vector<uint8_t> invalid(width, 0);
    for (int y = y0; y < y1; ++y)
    {
        const bool has_up = y > 0, has_down = y + 1 < height;
        const float* up = has_up ? q.depth.ptr<float>(y - 1) : zero_depth.data();
        const float* down = has_down ? q.depth.ptr<float>(y + 1) : zero_depth.data();
        const uint8_t* vup = has_up ? q.valid.ptr<uint8_t>(y - 1) : invalid.data();
        const uint8_t* vdown = has_down ? q.valid.ptr<uint8_t>(y + 1) : invalid.data();
        (laplacian ? levelsAndScalesRow<true> : levelsAndScalesRow<false>)(up, q.depth.ptr<float>(y), down, vup,
                                                                           q.valid.ptr<uint8_t>(y), vdown,
                                                                           q.reflectivity.ptr<float>(y), width, p,
                                                                           level.data(), scale.data(), hI.data());
        uint8_t* bgr = q.bgr.ptr<uint8_t>(y);
        uint8_t* gray = q.gray.ptr<uint8_t>(y);
        // Invalid pixels have scale 0: colour and gray round to 0.
        int x0 = 0;
#if defined(__SSE2__)
        // 4 lanes (b, g, r, luminance) per pixel: the same float operations, the truncation by cvtt and the
        // saturating packs (the luminance's min(255)). The 4-byte store also writes the next pixel's first
        // byte, which that pixel overwrites; the row's last pixel takes the scalar path (another thread's row
        // follows).
        const __m128 half = _mm_set1_ps(0.5f);
        for (; x0 + 1 < width; ++x0)
        {
            const __m128 v = _mm_add_ps(_mm_mul_ps(_mm_load_ps(hue.bgrl[level[x0]]), _mm_set1_ps(scale[x0])), half);
            __m128i i = _mm_cvttps_epi32(v);
            i = _mm_packs_epi32(i, i);
            i = _mm_packus_epi16(i, i);
            const uint32_t w = uint32_t(_mm_cvtsi128_si32(i));
            std::memcpy(bgr + 3 * x0, &w, sizeof w);
            gray[x0] = uint8_t(w >> 24);  // luminance mode; the other modes overwrite it below
        }
#endif
        for (int x = x0; x < width; ++x)
        {
            const float* c = hue.bgr[level[x]];
            const float sc = scale[x];
            bgr[3 * x] = uint8_t(c[0] * sc + 0.5f);
            bgr[3 * x + 1] = uint8_t(c[1] * sc + 0.5f);
            bgr[3 * x + 2] = uint8_t(c[2] * sc + 0.5f);
        }
        switch (gray_mode)
        {
            case GrayMode::Luminance:
                for (int x = x0; x < width; ++x)
                    gray[x] = uint8_t(std::min(255.0f, hue.luminance[level[x]] * scale[x] + 0.5f));
                break;
            case GrayMode::Value:
                for (int x = 0; x < width; ++x) gray[x] = uint8_t(std::min(255.0f, scale[x] + 0.5f));
                break;
            case GrayMode::ShadedReflectivity:
                for (int x = 0; x < width; ++x)
                    gray[x] = uint8_t(std::min(255.0f, (0.25f + 0.75f * hI[x]) * scale[x] + 0.5f));
                break;
        }
    }
}

}  // namespace quasiloc::quasi::detail
