// See-through filter: a far surface's sparse pixels showing through the gaps between a nearer surface's
// points are dropped before completion.
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

namespace
{
/** Candidates of one row: sparse pixels with a window neighbour nearer by the margin (the window minimum
 *  says so). Branch-free, so that it vectorises; the per-pixel branches it replaces were unpredictable. */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
void candidates(const float* __restrict depth, const float* __restrict wmin, float keep_factor, int width,
                uint8_t* __restrict cand)
{
    for (int x = 0; x < width; ++x) cand[x] = uint8_t((depth[x] < kNoDepth) & (wmin[x] < depth[x] * keep_factor));
}

#if defined(__SSE2__)
/** The sector mask of a window with SSE2: each window row in 4-column chunks, one compare and a table look-up
 *  of the 4 columns' sector bits per chunk. */
struct SectorChunks
{
    std::vector<ptrdiff_t> start;  ///< per chunk: offset of its first column from the pixel (in floats)
    std::vector<uint16_t> bits;    ///< per chunk, 16 entries: sector mask of the columns set in the entry
    SectorChunks(const SectorWindow& win, ptrdiff_t stride)
    {
        const int R = win.R, D = 2 * R + 1;
        for (int dy = -R; dy <= R; ++dy)
            for (int c = 0; c < (D + 3) / 4; ++c)
            {
                start.push_back(dy * stride - R + 4 * c);
                for (int m = 0; m < 16; ++m)
                {
                    uint16_t b = 0;
                    for (int l = 0; l < 4; ++l)
                    {
                        const int dx = -R + 4 * c + l;
                        if (!(m >> l & 1) || dx > R || (dx == 0 && dy == 0)) continue;
                        for (size_t k = 0; k < win.dx.size(); ++k)
                            if (win.dx[k] == dx && win.dy[k] == dy) b |= win.bit[k];
                    }
                    bits.push_back(b);
                }
            }
    }
    /** Needs 4 * chunks readable floats from x - R on every window row. */
    unsigned mask(const float* c, float threshold) const
    {
        const __m128 t = _mm_set1_ps(threshold);
        unsigned m = 0;
        for (size_t i = 0; i < start.size(); ++i)
            m |= bits[16 * i + unsigned(_mm_movemask_ps(_mm_cmplt_ps(_mm_loadu_ps(c + start[i]), t)))];
        return m;
    }
};
#endif
}  // namespace

void findSeeThrough(const SparsePlanes& sparse, const cv::Mat& window_min, int y0, int y1, const QuasiOptions& o,
                    std::vector<int32_t>& hidden)
{
    static const EmptyRunTable empty_runs;
    const SectorWindow win(o.occlusion_radius_px);
    const int R = win.R, width = sparse.depth.cols, height = sparse.depth.rows, M = sparse.margin;
    const size_t n_off = win.dx.size();
    const float keep_factor = float(1.0 - o.occlusion_depth_rel);
    // Surrounded: no run of empty sectors wider than the allowed gap.
    const int max_empty = int(std::floor(o.occlusion_max_gap_deg / SectorWindow::kSectorDeg + 1e-6));
    std::vector<ptrdiff_t> linear(n_off);  // offsets in floats, for pixels whose window is readable
    const ptrdiff_t stride = ptrdiff_t(sparse.depth.step1());
    for (size_t k = 0; k < n_off; ++k) linear[k] = win.dy[k] * stride + win.dx[k];
#if defined(__SSE2__)
    const SectorChunks chunks(win, stride);
    const int chunk_cols = 4 * ((2 * R + 1 + 3) / 4);  // columns read from x - R
#endif
    std::vector<uint8_t> cand(size_t(width) + 8, 0);
    for (int y = y0; y < y1; ++y)
    {
        const float* depth = sparse.depth.ptr<float>(y);
        const bool rows_readable = y - R >= -M && y + R < height + M;  // the margin holds empty pixels
        candidates(depth, window_min.ptr<float>(y), keep_factor, width, cand.data());
        for (int x0 = 0; x0 < width; x0 += 8)
        {
            uint64_t word;
            std::memcpy(&word, cand.data() + x0, sizeof word);  // 8 flags at once: most are all zero
            static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "flag x0 + i is byte i of the word");
            for (; word != 0; word &= word - 1)
            {
                const int x = x0 + __builtin_ctzll(word) / 8;
                // Pre-test passed (a nearer pixel in the window). Hidden: the nearer pixels surround it (it
                // shows through a gap of a nearer surface). Beside a nearer surface's edge they lie in a
                // half-plane that does not contain the pixel.
                const float threshold = depth[x] * keep_factor;
                unsigned mask = 0;
                const float* c = depth + x;
#if defined(__SSE2__)
                if (rows_readable && x - R >= -M && x - R + chunk_cols <= width + M)
                    mask = chunks.mask(c, threshold);
                else
#endif
                    if (rows_readable && x - R >= -M && x + R < width + M)
                    for (size_t k = 0; k < n_off; ++k) mask |= win.bit[k] & (0u - unsigned(c[linear[k]] < threshold));
                else
                    for (size_t k = 0; k < n_off; ++k)
                    {
                        const int xx = x + win.dx[k], yy = y + win.dy[k];
                        if (xx >= 0 && yy >= 0 && xx < width && yy < height &&
                            sparse.depth.ptr<float>(yy)[xx] < threshold)
                            mask |= win.bit[k];
                    }
                if (mask != 0 && empty_runs.run[mask] <= max_empty) hidden.push_back(y * width + x);
            }
        }
    }
}

}  // namespace quasiloc::quasi::detail
