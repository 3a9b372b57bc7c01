// Cross-guided completion of the sparse z-buffer image.
#include <algorithm>
#include <cmath>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "render_stages.h"

namespace quasiloc::quasi::detail
{
namespace
{
/** The completion window: offsets grouped by squared distance (for the nearest-neighbour searches) and,
 *  per window row, 4-lane chunks with their lane masks and squared distances (for the SIMD statistics). */
struct CompletionWindow
{
    struct Offset
    {
        int dx, dy, dist2;
    };
    int R = 0, D = 1, chunks = 1;
    std::vector<Offset> by_distance;  ///< sorted by dist2, then row-major
    std::vector<size_t> group_end;    ///< end of each run of equal dist2 in by_distance
    std::vector<int> group_of_dist2;  ///< [dist2]: index of its group (-1: no offset at that distance)
    std::vector<ptrdiff_t> linear;    ///< by_distance offsets in floats of a plane (set by setStride)
    std::vector<float> lane_dist2;    ///< [row][chunk][lane]; 1e9 for lanes outside the window
    explicit CompletionWindow(int radius) : R(radius), D(2 * radius + 1), chunks((D + 3) / 4)
    {
        for (int dy = -R; dy <= R; ++dy)
            for (int dx = -R; dx <= R; ++dx)
                if (dx || dy) by_distance.push_back({dx, dy, dx * dx + dy * dy});
        std::stable_sort(by_distance.begin(), by_distance.end(),
                         [](const Offset& a, const Offset& b) { return a.dist2 < b.dist2; });
        for (size_t i = 1; i <= by_distance.size(); ++i)
            if (i == by_distance.size() || by_distance[i].dist2 != by_distance[i - 1].dist2) group_end.push_back(i);
        group_of_dist2.assign(2 * R * R + 1, -1);
        for (size_t g = 0; g < group_end.size(); ++g) group_of_dist2[by_distance[group_end[g] - 1].dist2] = int(g);
        for (int dy = -R; dy <= R; ++dy)
            for (int c = 0; c < chunks; ++c)
                for (int l = 0; l < 4; ++l)
                {
                    const int dx = -R + 4 * c + l;
                    lane_dist2.push_back(dx <= R ? float(dx * dx + dy * dy) : 1e9f);
                }
    }
    void setStride(ptrdiff_t stride)
    {
        linear.clear();
        for (const auto& o : by_distance) linear.push_back(o.dy * stride + o.dx);
    }
    size_t groupBegin(size_t g) const { return g == 0 ? 0 : group_end[g - 1]; }
};

/** What completion computes for one empty pixel. */
struct WindowStats
{
    float i_max = -1;        ///< max reflectivity over the depth-consistent neighbours
    double depth_sum = 0;    ///< over the neighbours consistent in depth and reflectivity (exact in double:
    int count = 0;           ///< their depths lie within a few percent, so the order of summation is irrelevant)
    float min_dist2 = 1e9f;  ///< squared pixel distance of the nearest of them
};

struct Planes
{
    const SparsePlanes& p;
    int width, height;
    float depth(int x, int y) const { return p.depth.ptr<float>(y)[x]; }
    float refl(int x, int y) const { return p.refl.ptr<float>(y)[x]; }
    int32_t index(int x, int y) const { return p.index.ptr<int32_t>(y)[x]; }
    bool inside(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
};

/** Depth of the reference surface: the nearest sparse pixel in the image (ties: nearer depth). Empty
 *  pixels hold +inf, so a minimum needs no validity test. */
bool referenceDepth(const Planes& P, const CompletionWindow& w, int x, int y, bool inside, float& d_ref)
{
    const float* c = P.p.depth.ptr<float>(y) + x;
    for (size_t g = 0; g < w.group_end.size(); ++g)
    {
        float best = kNoDepth;
        for (size_t k = w.groupBegin(g); k < w.group_end[g]; ++k)
        {
            const auto& o = w.by_distance[k];
            if (inside)
                best = std::min(best, c[w.linear[k]]);
            else if (P.inside(x + o.dx, y + o.dy))
                best = std::min(best, P.depth(x + o.dx, y + o.dy));
        }
        if (best < kNoDepth)
        {
            d_ref = best;
            return true;
        }
    }
    return false;
}

inline bool depthConsistent(float d, float lo, float hi) { return d >= lo && d <= hi; }

/** Reference implementation of the window statistics (image borders, and non-SSE2 targets). */
WindowStats statsScalar(const Planes& P, const CompletionWindow& w, int x, int y, float lo, float hi, float rtol)
{
    WindowStats s;
    for (const auto& o : w.by_distance)
        if (P.inside(x + o.dx, y + o.dy) && depthConsistent(P.depth(x + o.dx, y + o.dy), lo, hi))
            s.i_max = std::max(s.i_max, P.refl(x + o.dx, y + o.dy));
    for (const auto& o : w.by_distance)
    {
        if (!P.inside(x + o.dx, y + o.dy)) continue;
        const float d = P.depth(x + o.dx, y + o.dy);
        if (!depthConsistent(d, lo, hi) || !(std::abs(P.refl(x + o.dx, y + o.dy) - s.i_max) <= rtol)) continue;
        s.depth_sum += d;
        ++s.count;
        s.min_dist2 = std::min(s.min_dist2, float(o.dist2));
    }
    return s;
}

#if defined(__SSE2__)
inline float hmax(__m128 v)
{
    v = _mm_max_ps(v, _mm_movehl_ps(v, v));
    return _mm_cvtss_f32(_mm_max_ss(v, _mm_shuffle_ps(v, v, 1)));
}
inline float hmin(__m128 v)
{
    v = _mm_min_ps(v, _mm_movehl_ps(v, v));
    return _mm_cvtss_f32(_mm_min_ss(v, _mm_shuffle_ps(v, v, 1)));
}

/** The same statistics, 4 lanes of a window row at a time. Needs the window rows inside the image and
 *  4 * chunks readable floats from x - R on every row. */
WindowStats statsSse2(const Planes& P, const CompletionWindow& w, int x, int y, float lo, float hi, float rtol)
{
    const __m128 vlo = _mm_set1_ps(lo), vhi = _mm_set1_ps(hi), minus1 = _mm_set1_ps(-1.0f);
    const __m128 sign = _mm_set1_ps(-0.0f), vrtol = _mm_set1_ps(rtol), big = _mm_set1_ps(1e9f);
    const float* d2 = w.lane_dist2.data();
    __m128 imax4 = minus1;
    for (int dy = -w.R; dy <= w.R; ++dy)
    {
        const float* rd = P.p.depth.ptr<float>(y + dy) + x - w.R;
        const float* rr = P.p.refl.ptr<float>(y + dy) + x - w.R;
        for (int c = 0; c < w.chunks; ++c, d2 += 4)
        {
            const __m128 d = _mm_loadu_ps(rd + 4 * c), r = _mm_loadu_ps(rr + 4 * c);
            const __m128 m =
                _mm_and_ps(_mm_and_ps(_mm_cmpge_ps(d, vlo), _mm_cmple_ps(d, vhi)), _mm_cmplt_ps(_mm_loadu_ps(d2), big));
            imax4 = _mm_max_ps(imax4, _mm_or_ps(_mm_and_ps(m, r), _mm_andnot_ps(m, minus1)));
        }
    }
    WindowStats s;
    s.i_max = hmax(imax4);
    const __m128 vimax = _mm_set1_ps(s.i_max), one = _mm_set1_ps(1.0f);
    __m128d sum_lo = _mm_setzero_pd(), sum_hi = _mm_setzero_pd();
    __m128 count4 = _mm_setzero_ps(), dmin4 = big;
    d2 = w.lane_dist2.data();
    for (int dy = -w.R; dy <= w.R; ++dy)
    {
        const float* rd = P.p.depth.ptr<float>(y + dy) + x - w.R;
        const float* rr = P.p.refl.ptr<float>(y + dy) + x - w.R;
        for (int c = 0; c < w.chunks; ++c, d2 += 4)
        {
            const __m128 d = _mm_loadu_ps(rd + 4 * c), r = _mm_loadu_ps(rr + 4 * c);
            const __m128 lane_d2 = _mm_loadu_ps(d2);
            const __m128 di = _mm_andnot_ps(sign, _mm_sub_ps(r, vimax));
            const __m128 m = _mm_and_ps(_mm_and_ps(_mm_cmpge_ps(d, vlo), _mm_cmple_ps(d, vhi)),
                                        _mm_and_ps(_mm_cmplt_ps(lane_d2, big), _mm_cmple_ps(di, vrtol)));
            const __m128 dm = _mm_and_ps(m, d);
            sum_lo = _mm_add_pd(sum_lo, _mm_cvtps_pd(dm));
            sum_hi = _mm_add_pd(sum_hi, _mm_cvtps_pd(_mm_movehl_ps(dm, dm)));
            count4 = _mm_add_ps(count4, _mm_and_ps(m, one));
            dmin4 = _mm_min_ps(dmin4, _mm_or_ps(_mm_and_ps(m, lane_d2), _mm_andnot_ps(m, big)));
        }
    }
    const __m128d sum2 = _mm_add_pd(sum_lo, sum_hi);
    s.depth_sum = _mm_cvtsd_f64(_mm_add_sd(sum2, _mm_unpackhi_pd(sum2, sum2)));
    count4 = _mm_add_ps(count4, _mm_movehl_ps(count4, count4));
    s.count = int(_mm_cvtss_f32(_mm_add_ss(count4, _mm_shuffle_ps(count4, count4, 1))));
    s.min_dist2 = hmin(dmin4);
    return s;
}
#endif

/** Provenance: among the consistent neighbours at squared distance min_dist2, the nearest in depth, then the
 *  smallest map index. */
int32_t provenanceOf(const Planes& P, const CompletionWindow& w, int x, int y, float lo, float hi, float rtol,
                     const WindowStats& s)
{
    float best_d = kNoDepth;
    int32_t best_i = -1;
    const size_t g = size_t(w.group_of_dist2[size_t(s.min_dist2)]);
    for (size_t k = w.groupBegin(g); k < w.group_end[g]; ++k)
    {
        const auto& o = w.by_distance[k];
        if (!P.inside(x + o.dx, y + o.dy)) continue;
        const float d = P.depth(x + o.dx, y + o.dy);
        if (!depthConsistent(d, lo, hi) || !(std::abs(P.refl(x + o.dx, y + o.dy) - s.i_max) <= rtol)) continue;
        const int32_t i = P.index(x + o.dx, y + o.dy);
        if (d < best_d || (d == best_d && i < best_i)) best_d = d, best_i = i;
    }
    return best_i;
}
/** Output rows of completeRows. */
struct OutRow
{
    float* depth;
    float* refl;
    int32_t* prov;
    uint8_t* valid;
    uint8_t* sparse;
};

/** The per-pixel path: pixel x of row y (any position; the window may leave the image). */
bool completePixel(const Planes& P, const CompletionWindow& win, int x, int y, float depth_rel, float rtol,
                   bool allow_simd, const OutRow& o)
{
    const int32_t si = P.index(x, y);
    if (si >= 0)
    {
        o.depth[x] = P.depth(x, y), o.refl[x] = P.refl(x, y), o.prov[x] = si, o.valid[x] = 255, o.sparse[x] = 255;
        return false;
    }
    o.depth[x] = 0, o.refl[x] = 0, o.prov[x] = -1, o.valid[x] = 0, o.sparse[x] = 0;
    const int R = win.R;
    const bool rows_inside = y - R >= 0 && y + R < P.height;
    const bool inside = rows_inside && x >= R && x + R < P.width;
    float d_ref;
    if (!referenceDepth(P, win, x, y, inside, d_ref)) return false;  // R >= 1: completeRows copies at radius 0

    // Reflectivity: the max over the neighbours on the reference's surface (depth-consistent); depth: the mean
    // over those also consistent in reflectivity with that max. Never mixes the two sides of a depth step:
    // every contributor lies within d_tol of d_ref.
    const float d_tol = depth_rel * d_ref, lo = d_ref - d_tol, hi = d_ref + d_tol;
    WindowStats s;
#if defined(__SSE2__)
    if (allow_simd && rows_inside && x - R >= 0 && x - R + 4 * win.chunks <= P.width)
        s = statsSse2(P, win, x, y, lo, hi, rtol);
    else
#endif
        s = statsScalar(P, win, x, y, lo, hi, rtol);
    (void)allow_simd;
    // count >= 1: the neighbour holding i_max qualifies.
    o.depth[x] = float(s.depth_sum / s.count);
    o.refl[x] = s.i_max;
    o.prov[x] = provenanceOf(P, win, x, y, lo, hi, rtol, s);
    o.valid[x] = 255;
    return true;
}

#if defined(__x86_64__) && defined(__GNUC__)
#define QUASILOC_COMPLETION_AVX2 1

/** [8-bit lane mask] -> 8 bytes of 0 / 255. */
struct ByteMasks
{
    uint64_t bytes[256];
    ByteMasks()
    {
        for (int m = 0; m < 256; ++m)
        {
            bytes[m] = 0;
            for (int l = 0; l < 8; ++l)
                if (m >> l & 1) bytes[m] |= uint64_t(0xff) << (8 * l);
        }
    }
};
const ByteMasks kByteMasks;

/** (best_d, best_i) = the lexicographic minimum of itself and (d, i) in the lanes of `m`. */
__attribute__((target("avx2"), always_inline)) inline void lexMinUpdate(__m256& best_d, __m256i& best_i, __m256 d,
                                                                        __m256i i, __m256 m)
{
    const __m256 smaller_i = _mm256_castsi256_ps(_mm256_cmpgt_epi32(best_i, i));
    const __m256 better = _mm256_or_ps(_mm256_cmp_ps(d, best_d, _CMP_LT_OQ),
                                       _mm256_and_ps(_mm256_cmp_ps(d, best_d, _CMP_EQ_OQ), smaller_i));
    const __m256 upd = _mm256_and_ps(m, better);
    best_d = _mm256_blendv_ps(best_d, d, upd);
    best_i = _mm256_castps_si256(_mm256_blendv_ps(_mm256_castsi256_ps(best_i), _mm256_castsi256_ps(i), upd));
}

/** The same rule as completePixel, vectorised over 8 pixels of a row instead of over the window: one lane per
 *  pixel, so every window offset is one unaligned load per plane and nothing is reduced across lanes. Pixels
 *  [x0, x1) of row y, x1 - x0 a multiple of 8; every window read must be readable (inside the plane or its
 *  margin, whose empty pixels need no test), the three planes must share one stride, and every distance group
 *  must have an even number of offsets (they go in pairs). Every operation is the scalar one lane by lane (no
 *  FMA: the target is plain AVX2), so the result is bit-identical. Depth sums are in double like the scalar
 *  path's (exact, so their order does not matter). `masks`: 8 floats per offset, 32-byte aligned (scratch).
 *  Returns the completed count. */
__attribute__((target("avx2"))) size_t completeSpanAvx2(const SparsePlanes& sp, const CompletionWindow& win, int y,
                                                        int x0, int x1, float depth_rel, float rtol, float* masks,
                                                        const OutRow& o)
{
    const float* D = sp.depth.ptr<float>(y);
    const float* RF = sp.refl.ptr<float>(y);
    const int32_t* I = sp.index.ptr<int32_t>(y);
    const ptrdiff_t* lin = win.linear.data();
    const size_t n_off = win.linear.size(), n_groups = win.group_end.size();
    const __m256 inf = _mm256_set1_ps(kNoDepth), minus1 = _mm256_set1_ps(-1.0f), zero = _mm256_setzero_ps();
    const __m256 vrel = _mm256_set1_ps(depth_rel), vrtol = _mm256_set1_ps(rtol);
    const __m256 abs_mask = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
    const __m256i minus1i = _mm256_set1_epi32(-1);
    size_t completed = 0;
    for (int x = x0; x < x1; x += 8)
    {
        const float* dc = D + x;
        const float* rc = RF + x;
        const int32_t* ic = I + x;
        const __m256i ci = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(ic));
        const __m256 is_sparse = _mm256_castsi256_ps(_mm256_cmpgt_epi32(ci, minus1i));
        const int sparse_bits = _mm256_movemask_ps(is_sparse);

        // Reference depth: the first distance group holding a sparse pixel, its minimum depth.
        __m256 d_ref = inf, found = zero;
        int found_bits = 0;
        for (size_t g = 0, k = 0; g < n_groups && (found_bits | sparse_bits) != 0xff; ++g)
        {
            __m256 gmin = inf;
            for (; k < win.group_end[g]; ++k) gmin = _mm256_min_ps(gmin, _mm256_loadu_ps(dc + lin[k]));
            const __m256 has = _mm256_cmp_ps(gmin, inf, _CMP_LT_OQ);
            d_ref = _mm256_blendv_ps(d_ref, gmin, _mm256_andnot_ps(found, has));
            found = _mm256_or_ps(found, has);
            found_bits = _mm256_movemask_ps(found);
        }
        const int completed_bits = found_bits & ~sparse_bits;
        const __m256 is_completed = _mm256_andnot_ps(is_sparse, found);
        __m256 depth_c = zero, refl_c = zero;
        __m256i prov_c = minus1i;
        if (completed_bits != 0)
        {
            const __m256 d_tol = _mm256_mul_ps(vrel, d_ref);
            const __m256 lo = _mm256_sub_ps(d_ref, d_tol), hi = _mm256_add_ps(d_ref, d_tol);
            // Every reduction below runs on two accumulators (even and odd offsets), combined at the end: the
            // loop-carried latency, not the throughput, bounds a single chain. The reductions are exact
            // (max, min, sums exact in double), so the split does not change the result.
            // i_max over the depth-consistent neighbours.
            __m256 i_max2[2] = {minus1, minus1};
            for (size_t k0 = 0; k0 < n_off; k0 += 2)
#pragma GCC unroll 2
                for (size_t j = 0; j < 2; ++j)
                {
                    const size_t k = k0 + j;
                    const __m256 d = _mm256_loadu_ps(dc + lin[k]), r = _mm256_loadu_ps(rc + lin[k]);
                    const __m256 m = _mm256_and_ps(_mm256_cmp_ps(d, lo, _CMP_GE_OQ), _mm256_cmp_ps(d, hi, _CMP_LE_OQ));
                    _mm256_store_ps(masks + 8 * k, m);  // depth-consistent, reused below
                    i_max2[j] = _mm256_max_ps(i_max2[j], _mm256_blendv_ps(minus1, r, m));
                }
            const __m256 i_max = _mm256_max_ps(i_max2[0], i_max2[1]);
            // Sum and count over the neighbours consistent in depth and reflectivity.
            __m256d sum_lo2[2] = {_mm256_setzero_pd(), _mm256_setzero_pd()};
            __m256d sum_hi2[2] = {_mm256_setzero_pd(), _mm256_setzero_pd()};
            __m256i count = _mm256_setzero_si256();
            for (size_t k0 = 0; k0 < n_off; k0 += 2)
#pragma GCC unroll 2
                for (size_t j = 0; j < 2; ++j)
                {
                    const size_t k = k0 + j;
                    const __m256 d = _mm256_loadu_ps(dc + lin[k]), r = _mm256_loadu_ps(rc + lin[k]);
                    const __m256 di = _mm256_and_ps(abs_mask, _mm256_sub_ps(r, i_max));
                    const __m256 m = _mm256_and_ps(_mm256_load_ps(masks + 8 * k), _mm256_cmp_ps(di, vrtol, _CMP_LE_OQ));
                    _mm256_store_ps(masks + 8 * k, m);  // consistent in both, for the provenance
                    const __m256 dm = _mm256_and_ps(m, d);
                    sum_lo2[j] = _mm256_add_pd(sum_lo2[j], _mm256_cvtps_pd(_mm256_castps256_ps128(dm)));
                    sum_hi2[j] = _mm256_add_pd(sum_hi2[j], _mm256_cvtps_pd(_mm256_extractf128_ps(dm, 1)));
                    count = _mm256_sub_epi32(count, _mm256_castps_si256(m));
                }
            const __m256d sum_lo = _mm256_add_pd(sum_lo2[0], sum_lo2[1]);
            const __m256d sum_hi = _mm256_add_pd(sum_hi2[0], sum_hi2[1]);
            // Provenance: in the nearest distance group holding a consistent neighbour, the minimum of
            // (depth, map index). Most pixels find it in the first groups.
            __m256 settled = _mm256_castsi256_ps(_mm256_castps_si256(is_completed) ^ minus1i);
            __m256 best_d[2] = {inf, inf};
            __m256i best_i[2] = {minus1i, minus1i};
            for (size_t g = 0, k = 0; g < n_groups && _mm256_movemask_ps(settled) != 0xff; ++g)
            {
                __m256 in_group = zero;
                for (; k < win.group_end[g]; k += 2)
#pragma GCC unroll 2
                    for (size_t j = 0; j < 2; ++j)
                    {
                        const __m256 d = _mm256_loadu_ps(dc + lin[k + j]);
                        const __m256i i = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(ic + lin[k + j]));
                        const __m256 m = _mm256_andnot_ps(settled, _mm256_load_ps(masks + 8 * (k + j)));
                        lexMinUpdate(best_d[j], best_i[j], d, i, m);
                        in_group = _mm256_or_ps(in_group, m);
                    }
                settled = _mm256_or_ps(settled, in_group);
            }
            lexMinUpdate(best_d[0], best_i[0], best_d[1], best_i[1], _mm256_castsi256_ps(minus1i));
            const __m256d mean_lo = _mm256_div_pd(sum_lo, _mm256_cvtepi32_pd(_mm256_castsi256_si128(count)));
            const __m256d mean_hi = _mm256_div_pd(sum_hi, _mm256_cvtepi32_pd(_mm256_extracti128_si256(count, 1)));
            depth_c = _mm256_set_m128(_mm256_cvtpd_ps(mean_hi), _mm256_cvtpd_ps(mean_lo));
            refl_c = i_max;
            prov_c = best_i[0];
            completed += size_t(__builtin_popcount(unsigned(completed_bits)));
        }
        // Sparse pixels keep their values; completed ones take the statistics; the others are empty.
        const __m256 depth_out = _mm256_blendv_ps(_mm256_and_ps(is_completed, depth_c), _mm256_loadu_ps(dc), is_sparse);
        const __m256 refl_out = _mm256_blendv_ps(_mm256_and_ps(is_completed, refl_c), _mm256_loadu_ps(rc), is_sparse);
        const __m256 prov_out =
            _mm256_blendv_ps(_mm256_blendv_ps(_mm256_castsi256_ps(minus1i), _mm256_castsi256_ps(prov_c), is_completed),
                             _mm256_castsi256_ps(ci), is_sparse);
        _mm256_storeu_ps(o.depth + x, depth_out);
        _mm256_storeu_ps(o.refl + x, refl_out);
        _mm256_storeu_ps(reinterpret_cast<float*>(o.prov + x), prov_out);
        std::memcpy(o.valid + x, &kByteMasks.bytes[sparse_bits | completed_bits], 8);
        std::memcpy(o.sparse + x, &kByteMasks.bytes[sparse_bits], 8);
    }
    return completed;
}

bool cpuHasAvx2()
{
    static const bool has = __builtin_cpu_supports("avx2");
    return has;
}
#endif

/** completeRows without a window (radius 0: the tracker's half-resolution render): the output is the sparse planes,
 *  pixel for pixel, as completePixel would write them, in a loop the compiler vectorises. */
void copySparseRows(const SparsePlanes& sparse, int y0, int y1, QuasiImage& out)
{
    const int W = sparse.depth.cols;
    for (int y = y0; y < y1; ++y)
    {
        const float* depth = sparse.depth.ptr<float>(y);
        const float* refl = sparse.refl.ptr<float>(y);
        const int32_t* index = sparse.index.ptr<int32_t>(y);
        float* o_depth = out.depth.ptr<float>(y);
        float* o_refl = out.reflectivity.ptr<float>(y);
        int32_t* o_prov = out.provenance.ptr<int32_t>(y);
        uint8_t* o_valid = out.valid.ptr<uint8_t>(y);
        uint8_t* o_sparse = out.sparse.ptr<uint8_t>(y);
        for (int x = 0; x < W; ++x)
        {
            const bool hit = index[x] >= 0;
            o_depth[x] = hit ? depth[x] : 0.0f;
            o_refl[x] = hit ? refl[x] : 0.0f;
            o_prov[x] = hit ? index[x] : -1;
            o_valid[x] = hit ? 255 : 0;
            o_sparse[x] = hit ? 255 : 0;
        }
    }
}
}  // namespace

size_t completeRows(const SparsePlanes& sparse, int y0, int y1, const QuasiOptions& o, QuasiImage& out, bool allow_simd)
{
    if (o.completion_radius_px == 0)
    {
        copySparseRows(sparse, y0, y1, out);
        return 0;
    }
    CompletionWindow win(o.completion_radius_px);
    win.setStride(ptrdiff_t(sparse.depth.step1()));
    const Planes P{sparse, sparse.depth.cols, sparse.depth.rows};
    const int R = win.R, M = sparse.margin, W = P.width;
    const float depth_rel = float(o.completion_depth_rel);
    const float rtol = float(o.completion_reflectivity_abs);
#if defined(QUASILOC_COMPLETION_AVX2)
    bool even_groups = true;  // the square window is symmetric: every distance group has 4 or 8 offsets
    for (size_t g = 0; g < win.group_end.size(); ++g) even_groups &= (win.group_end[g] - win.groupBegin(g)) % 2 == 0;
    const bool vector_rows = allow_simd && even_groups && cpuHasAvx2() && sparse.refl.step == sparse.depth.step &&
                             sparse.index.step == sparse.depth.step;
    // Pixels whose window columns are readable: x - R >= -M and x + R < W + M.
    const int xa = std::max(0, R - M);
    const int span_end = std::min(W, W + M - R);
    const int xb = xa + std::max(0, span_end - xa) / 8 * 8;
    // Per window offset, 8 lanes of consistency masks (32-byte aligned).
    std::vector<float> mask_buffer(8 * win.linear.size() + 8);
    float* masks = mask_buffer.data() + (8 - (reinterpret_cast<uintptr_t>(mask_buffer.data()) / sizeof(float)) % 8) % 8;
#endif
    size_t completed = 0;
    for (int y = y0; y < y1; ++y)
    {
        const OutRow row{out.depth.ptr<float>(y), out.reflectivity.ptr<float>(y), out.provenance.ptr<int32_t>(y),
                         out.valid.ptr<uint8_t>(y), out.sparse.ptr<uint8_t>(y)};
        int x = 0;
#if defined(QUASILOC_COMPLETION_AVX2)
        if (vector_rows && y - R >= -M && y + R < P.height + M && xb > xa)
        {
            for (; x < xa; ++x) completed += completePixel(P, win, x, y, depth_rel, rtol, allow_simd, row);
            completed += completeSpanAvx2(sparse, win, y, xa, xb, depth_rel, rtol, masks, row);
            x = xb;
        }
#endif
        for (; x < W; ++x) completed += completePixel(P, win, x, y, depth_rel, rtol, allow_simd, row);
    }
    return completed;
}

}  // namespace quasiloc::quasi::detail
