#include "canny_l2.h"

#include "scratch.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <quasiloc/core/error.h>
#include <type_traits>
#include <vector>

namespace quasiloc::estimation::detail
{
namespace
{
// Map codes, as OpenCV's: 0 a candidate not (yet) reached from a strong pixel, 1 no edge, 2 an edge.
constexpr uint8_t kCandidate = 0, kNone = 1, kEdge = 2;
// tan(22.5 deg) in OpenCV's fixed point (15 bits): the direction tests are |dy| 2^15 against |dx| TG22 and
// |dx| (TG22 + 2^16), tan(67.5 deg) = tan(22.5 deg) + 2.
constexpr int kShift = 15;
constexpr int kTg22 = int(0.4142135623730950488016887242097 * (1 << kShift) + 0.5);

using Int4 = int32_t __attribute__((vector_size(16)));
using Int8 = int32_t __attribute__((vector_size(32)));
using Short4 = int16_t __attribute__((vector_size(8)));
using Short8 = int16_t __attribute__((vector_size(16)));
using Byte4 = uint8_t __attribute__((vector_size(4)));
using Byte8 = uint8_t __attribute__((vector_size(8)));

/** N pixels at a time: int32 lanes for the norms and tests, int16 for the derivatives, bytes for the codes. */
template <int N>
struct Lanes
{
    static_assert(N == 4 || N == 8, "four lanes (SSE2) or eight (AVX2)");
    using Int = std::conditional_t<N == 4, Int4, Int8>;
    using Short = std::conditional_t<N == 4, Short4, Short8>;
    using Byte = std::conditional_t<N == 4, Byte4, Byte8>;
    using Bits = std::conditional_t<N == 4, uint32_t, uint64_t>;
    static constexpr Bits kEdgeBits = Bits(0x0202020202020202ull);  // kEdge in every byte

    // Results through references: an AVX vector returned by value from a function compiled for plain x86-64
    // would have an ABI of its own (these are always inlined into the AVX2 code anyway).
    [[gnu::always_inline]] static void load(const int* p, Int& v) { std::memcpy(&v, p, sizeof v); }
    [[gnu::always_inline]] static void loadWidened(const int16_t* p, Int& v)
    {
        Short s;
        std::memcpy(&s, p, sizeof s);
        v = __builtin_convertvector(s, Int);
    }
};

/** One pixel's code, as OpenCV's scalar loop decides it. `m`, `up`, `down`: this, the previous and the next row of
 *  squared norms (zero outside the image). */
uint8_t pixelCode(const int* m, const int* up, const int* down, int x, int xs, int ys, int low, int high)
{
    const int v = m[x];
    if (v <= low) return kNone;
    const int ax = std::abs(xs), ay = std::abs(ys) << kShift;
    const int tg22x = ax * kTg22;
    bool peak;
    if (ay < tg22x)
        peak = v > m[x - 1] && v >= m[x + 1];
    else if (ay > tg22x + (ax << (kShift + 1)))
        peak = v > up[x] && v >= down[x];
    else
    {
        const int s = (xs ^ ys) < 0 ? -1 : 1;
        peak = v > up[x - s] && v > down[x + s];
    }
    if (!peak) return kNone;
    return v > high ? kEdge : kCandidate;
}

/** Codes of one row, N pixels at a time without branches (the same tests as pixelCode); the strong pixels' map
 *  indices go on the stack at `top`. */
template <int N>
[[gnu::always_inline]] inline void suppressRowLanes(const int16_t* gx, const int16_t* gy, const int* m, const int* up,
                                                    const int* down, int width, int low, int high, uint8_t* row,
                                                    int row_index, int*& top)
{
    using L = Lanes<N>;
    using Int = typename L::Int;
    const Int low_v = Int{} + low, high_v = Int{} + high, tg22 = Int{} + kTg22;
    const Int zero{}, one = Int{} + kNone, two = Int{} + kEdge;
    int x = 0;
    for (; x + N <= width; x += N)
    {
        Int v, xs, ys, left, right, above, below, up_left, up_right, down_left, down_right;
        L::load(m + x, v);
        L::loadWidened(gx + x, xs);
        L::loadWidened(gy + x, ys);
        L::load(m + x - 1, left);
        L::load(m + x + 1, right);
        L::load(up + x, above);
        L::load(down + x, below);
        L::load(up + x - 1, up_left);
        L::load(up + x + 1, up_right);
        L::load(down + x - 1, down_left);
        L::load(down + x + 1, down_right);
        const Int ax = xs < 0 ? -xs : xs, ay = (ys < 0 ? -ys : ys) << kShift;
        const Int tg22x = ax * tg22;
        const Int horizontal = ay<tg22x, vertical = ay> tg22x + (ax << (kShift + 1));
        // Diagonal: the neighbours at (x - s, y - 1) and (x + s, y + 1), s = -1 when dx and dy differ in sign.
        const Int opposite = (xs ^ ys) < 0;
        const Int diag_up = opposite ? up_right : up_left;
        const Int diag_down = opposite ? down_left : down_right;
        const Int a = horizontal ? left : (vertical ? above : diag_up);
        const Int b = horizontal ? right : (vertical ? below : diag_down);
        const Int diagonal = ~(horizontal | vertical);
        const Int beyond_b = diagonal ? (v > b) : (v >= b);
        const Int peak = (v > low_v) & (v > a) & beyond_b;
        const Int code = peak ? ((v > high_v) ? two : zero) : one;
        const typename L::Byte bytes = __builtin_convertvector(code, typename L::Byte);
        std::memcpy(row + x, &bytes, sizeof bytes);
        typename L::Bits strong;
        std::memcpy(&strong, &bytes, sizeof strong);
        for (strong &= L::kEdgeBits; strong; strong &= strong - 1)
            *top++ = row_index + x + (__builtin_ctzll(strong) >> 3);
    }
    for (; x < width; ++x)
    {
        row[x] = pixelCode(m, up, down, x, gx[x], gy[x], low, high);
        if (row[x] == kEdge) *top++ = row_index + x;
    }
}

void suppressRowSse2(const int16_t* gx, const int16_t* gy, const int* m, const int* up, const int* down, int width,
                     int low, int high, uint8_t* row, int row_index, int*& top)
{
    suppressRowLanes<4>(gx, gy, m, up, down, width, low, high, row, row_index, top);
}

__attribute__((target("avx2"))) void suppressRowAvx2(const int16_t* gx, const int16_t* gy, const int* m, const int* up,
                                                     const int* down, int width, int low, int high, uint8_t* row,
                                                     int row_index, int*& top)
{
    suppressRowLanes<8>(gx, gy, m, up, down, width, low, high, row, row_index, top);
}
}  // namespace

void cannyL2(const cv::Mat& dx, const cv::Mat& dy, double low_threshold, double high_threshold, cv::Mat& edges,
             bool avx2)
{
    core::require(!dx.empty() && dx.type() == CV_16SC1 && dy.type() == CV_16SC1 && dx.size() == dy.size(), "cannyL2",
                  "dx and dy must be non-empty CV_16SC1 images of one size");
    // OpenCV's thresholds on the squared norm.
    if (low_threshold > high_threshold) std::swap(low_threshold, high_threshold);
    low_threshold = std::min(32767.0, low_threshold);
    high_threshold = std::min(32767.0, high_threshold);
    if (low_threshold > 0) low_threshold *= low_threshold;
    if (high_threshold > 0) high_threshold *= high_threshold;
    const int low = int(std::floor(low_threshold)), high = int(std::floor(high_threshold));

    // Squared norms and codes with a border of one pixel: zero norms, "no edge" codes. Reused per thread (two
    // pyramid levels are built at once): fresh buffers page-fault on every image. Taken by reference once: the
    // code is position-independent, and each use of a thread_local recomputed its address from the thread pointer
    // (the hysteresis did so several times per pixel).
    struct Scratch
    {
        std::vector<int> norm, stack;
        std::vector<uint8_t> map;
    };
    thread_local Scratch scratch;
    Scratch& s = scratch;
    const int W = dx.cols, H = dx.rows, stride = W + 2;
    // Every element read below is written first: the borders here, each row's norms and codes by its loop.
    growScratch(s.norm, size_t(stride) * size_t(H + 2));
    growScratch(s.map, size_t(stride) * size_t(H + 2));
    growScratch(s.stack, size_t(W) * size_t(H));  // a pixel goes on the stack once at most: when it becomes an edge
    std::fill_n(s.norm.begin(), stride, 0);
    std::fill_n(s.norm.begin() + ptrdiff_t(H + 1) * stride, stride, 0);
    std::memset(s.map.data(), kNone, size_t(stride));
    std::memset(s.map.data() + size_t(stride) * size_t(H + 1), kNone, size_t(stride));
    for (int y = 0; y < H; ++y)
    {
        const int16_t *gx = dx.ptr<int16_t>(y), *gy = dy.ptr<int16_t>(y);
        int* m = &s.norm[size_t(y + 1) * size_t(stride) + 1];
        m[-1] = m[W] = 0;
        for (int x = 0; x < W; ++x) m[x] = int(gx[x]) * gx[x] + int(gy[x]) * gy[x];
    }
    int* const bottom = s.stack.data();
    int* top = bottom;
    // Eight pixels per instruction where the CPU has AVX2 (the build targets plain x86-64): the same codes.
    static const bool has_avx2 = __builtin_cpu_supports("avx2");
    const auto suppressRow = avx2 && has_avx2 ? suppressRowAvx2 : suppressRowSse2;
    for (int y = 0; y < H; ++y)
    {
        const int first = (y + 1) * stride + 1;
        const int* m = &s.norm[size_t(first)];
        uint8_t* row = &s.map[size_t(first)];
        row[-1] = row[W] = kNone;
        suppressRow(dx.ptr<int16_t>(y), dy.ptr<int16_t>(y), m, m - stride, m + stride, W, low, high, row, first, top);
    }
    // Hysteresis: every candidate 8-connected to an edge becomes one.
    uint8_t* codes = s.map.data();
    while (top > bottom)
    {
        const int i = *--top;
        for (const int k :
             {i - 1, i + 1, i - stride - 1, i - stride, i - stride + 1, i + stride - 1, i + stride, i + stride + 1})
            if (codes[k] == kCandidate)
            {
                codes[k] = kEdge;
                *top++ = k;
            }
    }
    edges.create(H, W, CV_8UC1);
    for (int y = 0; y < H; ++y)
    {
        const uint8_t* row = &s.map[size_t(y + 1) * size_t(stride) + 1];
        uint8_t* out = edges.ptr<uint8_t>(y);
        for (int x = 0; x < W; ++x) out[x] = row[x] == kEdge ? 255 : 0;
    }
}
}  // namespace quasiloc::estimation::detail
