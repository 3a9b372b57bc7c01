// See-through filter and cross-guided completion of the sparse z-buffer image.
#include <algorithm>
#include <cmath>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "render_stages.h"

namespace quasiloc::quasi::detail
{
namespace
{
/** The see-through window: each offset's angular sector (16 sectors of 22.5 deg around the pixel) and, per
 *  16-bit mask of occupied sectors, the longest circular run of empty sectors. With 16 sectors, nearer pixels
 *  filling a half-plane that does not contain the pixel occupy at most 9 sectors (7 or more stay empty,
 *  157.5 deg), whatever the half-plane's direction. */
struct SectorWindow
{
    static constexpr int kSectors = 16;
    static constexpr float kSectorDeg = 360.0f / kSectors;
    int R = 0;
    std::vector<int> dx, dy;
    std::vector<uint16_t> bit;
    explicit SectorWindow(int radius) : R(radius)
    {
        for (int y = -R; y <= R; ++y)
            for (int x = -R; x <= R; ++x)
            {
                if (!x && !y) continue;
                double a = std::atan2(double(y), double(x)) * 180.0 / M_PI;
                if (a < 0) a += 360.0;
                dx.push_back(x);
                dy.push_back(y);
                bit.push_back(uint16_t(1u << std::min(kSectors - 1, int(a / kSectorDeg))));
            }
    }
};

struct EmptyRunTable
{
    std::vector<uint8_t> run;  ///< [mask]: longest circular run of empty sectors (16 for an empty mask)
    EmptyRunTable() : run(1u << SectorWindow::kSectors)
    {
        constexpr int S = SectorWindow::kSectors;
        for (uint32_t m = 0; m < run.size(); ++m)
        {
            int best = 0, cur = 0;
            for (int i = 0; i < 2 * S; ++i)  // twice around: circular runs
            {
                cur = (m >> (i % S)) & 1 ? 0 : cur + 1;
                best = std::max(best, std::min(cur, S));
            }
            run[m] = uint8_t(best);
        }
    }
};
}  // namespace

void findSeeThrough(const SparsePlanes& sparse, const cv::Mat& window_min, int y0, int y1, const QuasiOptions& o,
                    std::vector<int32_t>& hidden)
{
    static const EmptyRunTable empty_runs;
    const SectorWindow win(o.occlusion_radius_px);
    const int R = win.R, width = sparse.depth.cols, height = sparse.depth.rows;
    const size_t n_off = win.dx.size();
    const float keep_factor = float(1.0 - o.occlusion_depth_rel);
    // Surrounded: no run of empty sectors wider than the allowed gap.
    const int max_empty = int(std::floor(o.occlusion_max_gap_deg / SectorWindow::kSectorDeg + 1e-6));
    std::vector<ptrdiff_t> linear(n_off);  // offsets in floats, for pixels whose window is inside the image
    const ptrdiff_t stride = ptrdiff_t(sparse.depth.step1());
    for (size_t k = 0; k < n_off; ++k) linear[k] = win.dy[k] * stride + win.dx[k];
    for (int y = y0; y < y1; ++y)
    {
        const float* depth = sparse.depth.ptr<float>(y);
        const float* wmin = window_min.ptr<float>(y);
        const bool rows_inside = y >= R && y + R < height;
        for (int x = 0; x < width; ++x)
        {
            if (!(depth[x] < kNoDepth)) continue;
            // Pre-test: nothing in the window is nearer by the margin (true for most pixels).
            const float threshold = depth[x] * keep_factor;
            if (!(wmin[x] < threshold)) continue;
            // Hidden: the nearer pixels surround it (it shows through a gap of a nearer surface). Beside a
            // nearer surface's edge they lie in a half-plane that does not contain the pixel.
            unsigned mask = 0;
            if (rows_inside && x >= R && x + R < width)
            {
                const float* c = depth + x;
                for (size_t k = 0; k < n_off; ++k) mask |= win.bit[k] & (0u - unsigned(c[linear[k]] < threshold));
            }
            else
                for (size_t k = 0; k < n_off; ++k)
                {
                    const int xx = x + win.dx[k], yy = y + win.dy[k];
                    if (xx >= 0 && yy >= 0 && xx < width && yy < height && sparse.depth.ptr<float>(yy)[xx] < threshold)
                        mask |= win.bit[k];
                }
            if (mask != 0 && empty_runs.run[mask] <= max_empty) hidden.push_back(y * width + x);
        }
    }
}

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
    float i_max = -1;       ///< max reflectivity over the depth-consistent neighbours
    double depth_sum = 0;   ///< over the neighbours consistent in depth and reflectivity (exact in double:
    int count = 0;          ///< their depths lie within a few percent, so the order of summation is irrelevant)
    float min_dist2 = 1e9f; ///< squared pixel distance of the nearest of them
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
            const __m128 m = _mm_and_ps(_mm_and_ps(_mm_cmpge_ps(d, vlo), _mm_cmple_ps(d, vhi)),
                                        _mm_cmplt_ps(_mm_loadu_ps(d2), big));
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
}  // namespace

size_t completeRows(const SparsePlanes& sparse, int y0, int y1, const QuasiOptions& o, QuasiImage& out,
                    bool allow_simd)
{
    CompletionWindow win(o.completion_radius_px);
    win.setStride(ptrdiff_t(sparse.depth.step1()));
    const Planes P{sparse, sparse.depth.cols, sparse.depth.rows};
    const int R = win.R;
    const float depth_rel = float(o.completion_depth_rel);
    const float rtol = float(o.completion_reflectivity_abs);
    size_t completed = 0;
    for (int y = y0; y < y1; ++y)
    {
        const float* sd = sparse.depth.ptr<float>(y);
        const float* sr = sparse.refl.ptr<float>(y);
        const int32_t* si = sparse.index.ptr<int32_t>(y);
        float* depth = out.depth.ptr<float>(y);
        float* refl = out.reflectivity.ptr<float>(y);
        uint8_t* valid = out.valid.ptr<uint8_t>(y);
        uint8_t* is_sparse = out.sparse.ptr<uint8_t>(y);
        int32_t* prov = out.provenance.ptr<int32_t>(y);
        const bool rows_inside = y - R >= 0 && y + R < P.height;
        for (int x = 0; x < P.width; ++x)
        {
            if (si[x] >= 0)
            {
                depth[x] = sd[x], refl[x] = sr[x], prov[x] = si[x], valid[x] = 255, is_sparse[x] = 255;
                continue;
            }
            depth[x] = 0, refl[x] = 0, prov[x] = -1, valid[x] = 0, is_sparse[x] = 0;
            float d_ref;
            const bool inside = rows_inside && x >= R && x + R < P.width;
            if (R == 0 || !referenceDepth(P, win, x, y, inside, d_ref)) continue;

            // Reflectivity: the max over the neighbours on the reference's surface (depth-consistent); depth:
            // the mean over those also consistent in reflectivity with that max. Never mixes the two sides
            // of a depth step: every contributor lies within d_tol of d_ref.
            const float d_tol = depth_rel * d_ref, lo = d_ref - d_tol, hi = d_ref + d_tol;
            WindowStats s;
#if defined(__SSE2__)
            if (allow_simd && rows_inside && x - R >= 0 && x - R + 4 * win.chunks <= P.width)
                s = statsSse2(P, win, x, y, lo, hi, rtol);
            else
#endif
                s = statsScalar(P, win, x, y, lo, hi, rtol);
            // count >= 1: the neighbour holding i_max qualifies.
            depth[x] = float(s.depth_sum / s.count);
            refl[x] = s.i_max;
            prov[x] = provenanceOf(P, win, x, y, lo, hi, rtol, s);
            valid[x] = 255;
            ++completed;
        }
    }
    return completed;
}

}  // namespace quasiloc::quasi::detail
