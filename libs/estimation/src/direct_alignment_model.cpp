// The two sides of the direct alignment: map edges and NMI samples from a quasi-image, and the camera's
// distance-transform pyramid.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>
#include <opencv2/imgproc.hpp>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <quasiloc/core/error.h>
#include <quasiloc/estimation/direct_alignment.h>

#include "canny_l2.h"
#include "direct_alignment_detail.h"
#include "scratch.h"

namespace quasiloc::estimation
{
namespace detail
{
int32_t kthSmallest(const std::vector<int32_t>& values, size_t k)
{
    constexpr int shift = 11;
    constexpr size_t buckets = (size_t(1) << (22 - shift)) + 1, low_mask = (size_t(1) << shift) - 1;
    // Four histograms, one per lane of four: neighbouring pixels often fall in one bucket, and a counter
    // incremented back to back waits for its own store each time.
    std::vector<uint32_t> count(4 * buckets, 0);
    const size_t n = values.size();
    size_t i = 0;
    for (; i + 4 <= n; i += 4)
        for (size_t lane = 0; lane < 4; ++lane) ++count[lane * buckets + size_t(values[i + lane] >> shift)];
    for (; i < n; ++i) ++count[size_t(values[i] >> shift)];
    const auto inBucket = [&](size_t b) {
        return size_t(count[b]) + count[buckets + b] + count[2 * buckets + b] + count[3 * buckets + b];
    };
    size_t bucket = 0, below = 0;
    while (below + inBucket(bucket) <= k) below += inBucket(bucket++);
    std::vector<uint32_t> fine(low_mask + 1, 0);
    for (const int32_t v : values)
        if (size_t(v >> shift) == bucket) ++fine[size_t(v) & low_mask];
    size_t low = 0;
    while (below + fine[low] <= k) below += fine[low++];
    return int32_t((bucket << shift) | low);
}
}  // namespace detail

namespace
{
/** Picks at most `budget` of `pixels` spread over cells of `cell_px`: round-robin over the cells (the k-th
 *  pixel of every cell before the (k+1)-th of any), so dense edge clusters do not crowd out sparse ones.
 *  Deterministic (raster order within a cell). */
std::vector<cv::Point> spreadPixels(const std::vector<cv::Point>& pixels, cv::Size size, int cell_px, size_t budget)
{
    if (pixels.size() <= budget) return pixels;
    const int cols = (size.width + cell_px - 1) / cell_px, rows = (size.height + cell_px - 1) / cell_px;
    std::vector<std::vector<cv::Point>> cells(size_t(cols) * size_t(rows));
    for (const cv::Point& p : pixels) cells[size_t(p.y / cell_px) * size_t(cols) + size_t(p.x / cell_px)].push_back(p);
    std::vector<cv::Point> out;
    out.reserve(budget);
    for (size_t k = 0; out.size() < budget; ++k)
        for (const auto& c : cells)
            if (k < c.size() && out.size() < budget) out.push_back(c[k]);
    return out;
}

/** Pixels on the near side of depth discontinuities. Inverse depth w = 1/z is affine in the pixel coordinates
 *  on any plane, so a slanted surface (a road seen at a grazing angle changes depth by several percent per
 *  pixel) has constant steps of w, while a discontinuity is a step far larger than the steps beside it. A pair
 *  (p, q) of neighbours along x or y is an edge when q is farther by more than rel (relative in w) and the step
 *  exceeds `slope_factor` times the larger of the steps just before p and just after q (when those exist). */
void depthEdgePixels(const cv::Mat& depth, const cv::Mat& valid, double rel, cv::Mat& mark)
{
    constexpr double slope_factor = 3.0;
    const int W = depth.cols, H = depth.rows;
    // The inverse depths once per pixel, NaN where there is none, with a border of two NaN pixels (the tests
    // reach two pixels beyond a pair): each pixel takes part in up to eight tests.
    constexpr int kBorder = 2;
    const int stride = W + 2 * kBorder;
    std::vector<double> inverse(size_t(stride) * size_t(H + 2 * kBorder), std::numeric_limits<double>::quiet_NaN());
    for (int y = 0; y < H; ++y)
    {
        const float* d = depth.ptr<float>(y);
        const uint8_t* v = valid.ptr<uint8_t>(y);
        double* out = &inverse[size_t(y + kBorder) * size_t(stride) + kBorder];
        for (int x = 0; x < W; ++x)
            if (v[x] && d[x] > 0) out[x] = 1.0 / double(d[x]);
    }
    const auto w = [&](int x, int y) { return inverse[size_t(y + kBorder) * size_t(stride) + size_t(x + kBorder)]; };
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (const auto& [dx, dy] : {std::pair{1, 0}, {0, 1}})
            {
                const double a = w(x, y), b = w(x + dx, y + dy);
                if (std::isnan(a) || std::isnan(b)) continue;
                const double step = std::abs(a - b);
                if (step <= rel * std::max(a, b)) continue;
                const double before = std::abs(w(x - dx, y - dy) - a), after = std::abs(w(x + 2 * dx, y + 2 * dy) - b);
                double slope = 0;
                if (!std::isnan(before)) slope = std::max(slope, before);
                if (!std::isnan(after)) slope = std::max(slope, after);
                if (step <= slope_factor * slope) continue;
                if (a > b)
                    mark.at<uint8_t>(y, x) = 255;  // the near side (larger inverse depth)
                else
                    mark.at<uint8_t>(y + dy, x + dx) = 255;
            }
}

/** The planes reduced by `block` x `block` pixels to the nearest surface: depth = the minimum valid depth of
 *  the block (far points seen through the gaps of a sparse near surface do not count), reflectivity = the
 *  mean over the block's pixels on that surface (within rel of the minimum). On a sparse map (a 64-beam scan
 *  seen from a camera) the full-resolution planes are speckled with holes, and every hole would make depth
 *  and reflectivity "edges"; blocks are dense. */
void reduceToBlocks(const cv::Mat& depth, const cv::Mat& refl, const cv::Mat& valid, int block, double rel,
                    cv::Mat& d_out, cv::Mat& r_out, cv::Mat& v_out)
{
    const int W = depth.cols / block, H = depth.rows / block;
    d_out = cv::Mat::zeros(H, W, CV_32FC1);
    r_out = cv::Mat::zeros(H, W, CV_32FC1);
    v_out = cv::Mat::zeros(H, W, CV_8UC1);
    for (int by = 0; by < H; ++by)
        for (int bx = 0; bx < W; ++bx)
        {
            const int x0 = bx * block, x1 = x0 + block;
            float dmin = std::numeric_limits<float>::infinity();
            for (int y = by * block; y < (by + 1) * block; ++y)
            {
                const float* d = depth.ptr<float>(y);
                const uint8_t* v = valid.ptr<uint8_t>(y);
                for (int x = x0; x < x1; ++x)
                    if (v[x] && d[x] > 0) dmin = std::min(dmin, d[x]);
            }
            if (!std::isfinite(dmin)) continue;
            const float lim = dmin * float(1.0 + rel);
            double sum = 0;
            int n = 0;
            for (int y = by * block; y < (by + 1) * block; ++y)
            {
                const float *d = depth.ptr<float>(y), *r = refl.ptr<float>(y);
                const uint8_t* v = valid.ptr<uint8_t>(y);
                for (int x = x0; x < x1; ++x)
                    if (v[x] && d[x] > 0 && d[x] <= lim) sum += r[x], ++n;
            }
            d_out.at<float>(by, bx) = dmin;
            r_out.at<float>(by, bx) = float(sum / n);
            v_out.at<uint8_t>(by, bx) = 255;
        }
}

Eigen::Vector3d liftPixel(const core::CameraModel& camera, const Eigen::Isometry3d& T_world_cam, const cv::Point& p,
                          float depth)
{
    return T_world_cam * (double(depth) * camera.unproject(Eigen::Vector2d(p.x, p.y)));
}

/** Canny edges with thresholds from the gradient-magnitude distribution of the image (every other pixel of
 *  every other row is enough for a percentile): the same share of pixels is "strong" whatever the exposure or
 *  contrast. `dx`, `dy`: the image's 3x3 Sobel derivatives (CV_16S), also used for the edge orientations. */
void cannyByPercentile(const cv::Mat& dx, const cv::Mat& dy, double high_percentile, double low_ratio, cv::Mat& edges)
{
    // Squared magnitudes, exact in int32 (|gx|, |gy| <= 1020 for a 3x3 Sobel of 8-bit pixels): they sort as the
    // magnitudes do, so only the chosen one needs its square root.
    std::vector<int32_t> squared;
    squared.reserve(dx.total() / 4 + 1);
    for (int y = 0; y < dx.rows; y += 2)
    {
        const int16_t* gx = dx.ptr<int16_t>(y);
        const int16_t* gy = dy.ptr<int16_t>(y);
        for (int x = 0; x < dx.cols; x += 2)
            if (gx[x] || gy[x]) squared.push_back(int32_t(gx[x]) * gx[x] + int32_t(gy[x]) * gy[x]);
    }
    double high = 50;
    if (!squared.empty())
    {
        const size_t k = std::min(squared.size() - 1, size_t(squared.size() * high_percentile / 100.0));
        // A float square root: its rounding decides which pixels reach the threshold, and the edge fields the
        // tracker was measured with come from this one.
        high = std::max(1.0, double(std::sqrt(float(detail::kthSmallest(squared, k)))));
    }
    detail::cannyL2(dx, dy, low_ratio * high, high, edges);  // cv::Canny(dx, dy, edges, low, high, true)
}

/** Calls f(x) for every non-zero byte of row[0 .. width): 16 bytes at a time (edge pixels are a few percent of
 *  an image: a branch per pixel mispredicts at every edge). */
template <class F>
void forEachNonZero(const uint8_t* row, int width, F&& f)
{
    int x = 0;
#if defined(__SSE2__)
    const __m128i zero = _mm_setzero_si128();
    for (; x + 16 <= width; x += 16)
    {
        const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(row + x));
        unsigned mask = ~unsigned(_mm_movemask_epi8(_mm_cmpeq_epi8(v, zero))) & 0xffffu;
        for (; mask; mask &= mask - 1) f(x + __builtin_ctz(mask));
    }
#endif
    for (; x < width; ++x)
        if (row[x]) f(x);
}
}  // namespace

DirectAlignmentModel buildDirectAlignmentModel(const DirectAlignmentOptions& o, const cv::Mat& depth,
                                               const cv::Mat& reflectivity, const cv::Mat& valid, const cv::Mat& sparse,
                                               const core::CameraModel& camera, const Eigen::Isometry3d& T_world_cam,
                                               int downscale)
{
    const std::string in = "direct alignment model";
    core::require(downscale >= 1 && o.model_block_px % downscale == 0, in,
                  "downscale " + std::to_string(downscale) + " must be >= 1 and divide model_block_px (" +
                      std::to_string(o.model_block_px) + ")");
    core::require(!depth.empty() && depth.type() == CV_32FC1, in, "depth must be a non-empty CV_32FC1 image");
    core::require(reflectivity.size() == depth.size() && reflectivity.type() == CV_32FC1, in,
                  "reflectivity must be CV_32FC1 of the depth's size");
    core::require(valid.size() == depth.size() && valid.type() == CV_8UC1, in,
                  "valid must be CV_8UC1 of the depth's size");
    core::require(sparse.size() == depth.size() && sparse.type() == CV_8UC1, in,
                  "sparse must be CV_8UC1 of the depth's size");
    core::require(camera.width == depth.cols && camera.height == depth.rows, in,
                  "the camera model's size differs from the planes'");

    // Edges are found on block-reduced planes (see reduceToBlocks) and lifted from the block centre.
    const int B = o.model_block_px / downscale;
    cv::Mat d_b, r_b, v_b;
    reduceToBlocks(depth, reflectivity, valid, B, o.depth_edge_rel, d_b, r_b, v_b);
    // Closing of the inverse depth fills the holes of a sparse near surface through which farther points show
    // (each such hole would otherwise be ringed by false depth edges) and keeps real silhouettes in place.
    cv::Mat inv_depth = cv::Mat::zeros(d_b.size(), CV_32FC1), closed_depth, closed_valid;
    for (int y = 0; y < d_b.rows; ++y)
        for (int x = 0; x < d_b.cols; ++x)
            if (v_b.at<uint8_t>(y, x)) inv_depth.at<float>(y, x) = 1.0f / d_b.at<float>(y, x);
    if (o.model_close_px > 0)
        cv::morphologyEx(
            inv_depth, inv_depth, cv::MORPH_CLOSE,
            cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * o.model_close_px + 1, 2 * o.model_close_px + 1)));
    closed_valid = inv_depth > 0;
    cv::divide(1.0, inv_depth, closed_depth);
    closed_depth.setTo(0, closed_valid == 0);
    d_b = closed_depth;
    cv::Mat mark = cv::Mat::zeros(d_b.size(), CV_8UC1);
    depthEdgePixels(d_b, closed_valid, o.depth_edge_rel, mark);
    const cv::Mat depth_mark = mark.clone();
    // Normals: of the inverse depth at depth edges, of the reflectivity at reflectivity edges.
    cv::Mat n_depth_x, n_depth_y, n_refl_x, n_refl_y;
    cv::Sobel(inv_depth, n_depth_x, CV_32F, 1, 0, 3);
    cv::Sobel(inv_depth, n_depth_y, CV_32F, 0, 1, 3);
    cv::Sobel(r_b, n_refl_x, CV_32F, 1, 0, 3);
    cv::Sobel(r_b, n_refl_y, CV_32F, 0, 1, 3);
    if (o.use_reflectivity_edges)
    {
        // Canny on the map reflectivity where the map has values; the border of the valid region (e.g. the
        // LiDAR's upper field-of-view limit) is not an edge of the scene, so it is eroded away.
        cv::Mat refl8, inner, refl_edges;
        r_b.convertTo(refl8, CV_8U, 255.0);
        cv::GaussianBlur(refl8, refl8, cv::Size(3, 3), 0);
        cv::erode(v_b, inner, cv::Mat(), cv::Point(-1, -1), 2);
        const double high = o.refl_canny_high * 255.0 * 4.0;  // Sobel 3x3 gain is 4 for a unit step
        cv::Canny(refl8, refl_edges, 0.5 * high, high, 3, true);
        refl_edges.setTo(0, inner == 0);
        mark |= refl_edges;
    }
    std::vector<cv::Point> edge_blocks;
    cv::findNonZero(mark, edge_blocks);
    edge_blocks = spreadPixels(edge_blocks, d_b.size(), std::max(1, 16 / o.model_block_px), size_t(o.max_edge_points));

    DirectAlignmentModel model;
    model.edge_points_world.reserve(edge_blocks.size());
    const OrientationClasses orientation(o.orientation_bins);
    for (const cv::Point& b : edge_blocks)
    {
        const bool is_depth = depth_mark.at<uint8_t>(b) != 0;
        model.edge_bin.push_back(
            uint8_t(orientation.classOf(is_depth ? n_depth_x.at<float>(b) : n_refl_x.at<float>(b),
                                        is_depth ? n_depth_y.at<float>(b) : n_refl_y.at<float>(b))));
        const Eigen::Vector2d u((b.x + 0.5) * B - 0.5, (b.y + 0.5) * B - 0.5);  // block centre, full pixels
        model.edge_points_world.push_back(T_world_cam * (double(d_b.at<float>(b)) * camera.unproject(u)));
    }

    return model;
}

NmiSamples buildNmiSamples(const DirectAlignmentOptions& o, const cv::Mat& depth, const cv::Mat& reflectivity,
                           const cv::Mat& sparse, const core::CameraModel& camera, const Eigen::Isometry3d& T_world_cam)
{
    const std::string in = "NMI samples";
    core::require(!depth.empty() && depth.type() == CV_32FC1, in, "depth must be a non-empty CV_32FC1 image");
    core::require(reflectivity.size() == depth.size() && reflectivity.type() == CV_32FC1, in,
                  "reflectivity must be CV_32FC1 of the depth's size");
    core::require(sparse.size() == depth.size() && sparse.type() == CV_8UC1, in,
                  "sparse must be CV_8UC1 of the depth's size");
    std::vector<cv::Point> pixels;
    cv::findNonZero(sparse, pixels);
    pixels = spreadPixels(pixels, depth.size(), 16, size_t(o.max_nmi_points));
    NmiSamples samples;
    for (const cv::Point& p : pixels)
    {
        if (!(depth.at<float>(p) > 0)) continue;
        samples.points_world.push_back(liftPixel(camera, T_world_cam, p, depth.at<float>(p)));
        samples.reflectivity.push_back(std::clamp(reflectivity.at<float>(p), 0.0f, 1.0f));
    }
    return samples;
}

OrientationClasses::OrientationClasses(int bins) : bins_(bins)
{
    core::require(bins >= 1 && bins <= 64, "OrientationClasses", "bins must be in [1, 64]");
    for (int k = 1; k <= bins; ++k)
    {
        cos_.push_back(float(std::cos(k * M_PI / (2 * bins))));
        sin_.push_back(float(std::sin(k * M_PI / (2 * bins))));
    }
    if (bins > 8) return;
    for (int sector = 0; sector < 2 * bins; ++sector)
    {
        int second = 0;
        const int b = classOfSector(sector, &second);
        sector_bits_.push_back(uint8_t((1u << b) | (1u << second)));
    }
}

void OrientationClasses::pairBits(const float* gx_in, const float* gy_in, size_t n, uint8_t* bits) const
{
    core::require(bins_ <= 8, "OrientationClasses::pairBits", "needs at most 8 bins");
    // classOf's arithmetic on four lanes: the same float products, differences and comparisons (plain x86-64 has
    // no fused multiply-add to change them), the same folding.
    using F4 = float __attribute__((vector_size(16)));
    using I4 = int32_t __attribute__((vector_size(16)));
    size_t i = 0;
    for (; i + 4 <= n; i += 4)
    {
        F4 gx, gy;
        std::memcpy(&gx, gx_in + i, sizeof gx);
        std::memcpy(&gy, gy_in + i, sizeof gy);
        const I4 flip = (gy < 0) | ((gy == 0) & (gx < 0));
        gx = flip ? -gx : gx;
        gy = flip ? -gy : gy;
        const I4 mirrored = gx < 0;
        I4 abs_bits;
        std::memcpy(&abs_bits, &gx, sizeof gx);
        abs_bits &= I4{} + 0x7fffffff;  // std::abs: the sign bit cleared
        F4 u;
        std::memcpy(&u, &abs_bits, sizeof u);
        I4 below{};
        for (size_t k = 0; k < cos_.size(); ++k) below -= (u * sin_[k] - gy * cos_[k] <= 0);  // true is -1
        const I4 sector = mirrored ? (2 * bins_ - 1) - below : below;
        for (int lane = 0; lane < 4; ++lane) bits[i + size_t(lane)] = sector_bits_[size_t(sector[lane])];
    }
    for (; i < n; ++i) bits[i] = sector_bits_[size_t(sectorOf(gx_in[i], gy_in[i]))];
}

int OrientationClasses::classOf(float gx, float gy, int* second) const
{
    int neighbour = 0;
    const int b = classOfSector(sectorOf(gx, gy), &neighbour);
    if (second) *second = neighbour;
    return b;
}

int OrientationClasses::sectorOf(float gx, float gy) const
{
    // Without atan2 (a tenth of the camera side's cost): the angle mod 180 deg falls in one of 2 * bins sectors of
    // 90 / bins deg between class centres and class borders. Folded into the first quadrant, the sector is told by
    // the signs of the cross products with the `bins` borders up to 90 deg (the other quadrant mirrors it).
    if (gy < 0 || (gy == 0 && gx < 0)) gx = -gx, gy = -gy;  // the same line: angle mod 180 deg into [0, 180)
    const bool mirrored = gx < 0;
    const float u = std::abs(gx);
    int below = 0;  // borders k * 90 / bins deg (k = 1 .. bins) at or below the folded angle
    for (size_t k = 0; k < cos_.size(); ++k) below += u * sin_[k] - gy * cos_[k] <= 0;
    return mirrored ? 2 * bins_ - 1 - below : below;
}

int OrientationClasses::classOfSector(int sector, int* second) const
{
    // In sector s the nearest class is (s + 1) / 2, and the angle leans to the next class when s is even. Every
    // value below is in [0, 2 * bins): a subtraction instead of an integer division (most of classOf's cost when
    // it was a %).
    const auto wrap = [this](int v) { return v >= bins_ ? v - bins_ : v; };
    const int b = wrap((sector + 1) / 2);
    *second = wrap(sector % 2 == 0 ? b + 1 : b + bins_ - 1);
    return b;
}

namespace
{
/** Eight int16 lanes per pixel, one per orientation class (classDistanceTransforms). */
using Lanes = int16_t __attribute__((vector_size(16)));

/** The lanes of row `y` (0-based; the buffer has a one-pixel border): `far` where the pixel is not in the class,
 *  0 where it is. Branch-free: the bits, broadcast to all lanes, tested against each lane's class bit. */
void initLanes(const uint8_t* bits, int W, Lanes far_v, Lanes* row)
{
    const Lanes class_bit = {1, 2, 4, 8, 16, 32, 64, 128};
    row[0] = row[W + 1] = far_v;
    for (int x = 0; x < W; ++x)
    {
        const Lanes in_class = ((Lanes{} + int16_t(bits[x])) & class_bit) != 0;  // -1 in the pixel's classes
        row[x + 1] = far_v & ~in_class;
    }
}

/** One class's lane of a finished pixel back to pixels, truncated. */
inline float lanePixels(int16_t lane, float inv_s, float truncation)
{
    const float f = float(lane) * inv_s;
    return f < truncation ? f : truncation;
}

/** Pixels x0 .. x0 + 7 of a finished row, back to pixels (lane / s, truncated), one float row per class. The
 *  same arithmetic as one pixel at a time; an 8 x 8 transpose first, so each class is stored 8 floats at once. */
void storeEightPixels(const Lanes* px, int classes, float inv_s, float truncation, float* const* out, int x0)
{
#if defined(__SSE2__)
    __m128i r[8], t[8], u[8], c[8];
    for (int i = 0; i < 8; ++i) r[i] = _mm_load_si128(reinterpret_cast<const __m128i*>(px + i));
    for (int i = 0; i < 4; ++i)  // pairs of pixels: classes 0-3, then 4-7
    {
        t[i] = _mm_unpacklo_epi16(r[2 * i], r[2 * i + 1]);
        t[i + 4] = _mm_unpackhi_epi16(r[2 * i], r[2 * i + 1]);
    }
    for (int h = 0; h < 2; ++h)  // quadruples of pixels (0-3, 4-7): two classes each
    {
        u[4 * h + 0] = _mm_unpacklo_epi32(t[2 * h], t[2 * h + 1]);      // classes 0, 1
        u[4 * h + 1] = _mm_unpackhi_epi32(t[2 * h], t[2 * h + 1]);      // classes 2, 3
        u[4 * h + 2] = _mm_unpacklo_epi32(t[2 * h + 4], t[2 * h + 5]);  // classes 4, 5
        u[4 * h + 3] = _mm_unpackhi_epi32(t[2 * h + 4], t[2 * h + 5]);  // classes 6, 7
    }
    for (int q = 0; q < 4; ++q)  // the eight pixels of classes 2q and 2q + 1
    {
        c[2 * q] = _mm_unpacklo_epi64(u[q], u[q + 4]);
        c[2 * q + 1] = _mm_unpackhi_epi64(u[q], u[q + 4]);
    }
    const __m128 vinv = _mm_set1_ps(inv_s), vtrunc = _mm_set1_ps(truncation);
    for (int k = 0; k < classes; ++k)
    {
        const __m128i lo = _mm_srai_epi32(_mm_unpacklo_epi16(c[k], c[k]), 16);  // sign-extended to int32
        const __m128i hi = _mm_srai_epi32(_mm_unpackhi_epi16(c[k], c[k]), 16);
        _mm_storeu_ps(out[k] + x0, _mm_min_ps(_mm_mul_ps(_mm_cvtepi32_ps(lo), vinv), vtrunc));
        _mm_storeu_ps(out[k] + x0 + 4, _mm_min_ps(_mm_mul_ps(_mm_cvtepi32_ps(hi), vinv), vtrunc));
    }
#else
    for (int i = 0; i < 8; ++i)
        for (int k = 0; k < classes; ++k) out[k][x0 + i] = lanePixels(px[i][k], inv_s, truncation);
#endif
}
}  // namespace

void classDistanceTransforms(const cv::Mat& class_bits, int classes, double truncation_px,
                             std::vector<cv::Mat>& distance)
{
    core::require(!class_bits.empty() && class_bits.type() == CV_8UC1, "classDistanceTransforms",
                  "class_bits must be a non-empty CV_8UC1 image");
    core::require(classes >= 1 && classes <= kMaxFusedClasses, "classDistanceTransforms", "classes must be in [1, 8]");
    core::require(truncation_px >= 1 && truncation_px <= 1000, "classDistanceTransforms",
                  "truncation_px must be in [1, 1000]");
    // Eight int16 lanes per pixel, one per class, in units of 1/s pixel: every min and add below acts on all the
    // classes at once (SSE2 pminsw/paddw), so the two passes cost about what one class's transform costs. The
    // weights are OpenCV's DIST_L2 / DIST_MASK_3 (0.955 along an axis, 1.3693 along a diagonal) to 1/s; no
    // value exceeds `far`, so no add overflows.
    const auto vmin = [](Lanes a, Lanes b) { return a < b ? a : b; };
    const double s = std::floor(30000.0 / (truncation_px + 1.37));  // (truncation + diagonal) * s < 32767
    const int16_t axis = int16_t(std::lround(0.955 * s)), diag = int16_t(std::lround(1.3693 * s));
    const int16_t far = int16_t(32767 - diag - 1);
    const Lanes a = Lanes{} + axis, d = Lanes{} + diag, far_v = Lanes{} + far;
    const int W = class_bits.cols, H = class_bits.rows, stride = W + 2;
    // The buffer outlives the call (per thread: the pyramid's levels are built on two threads): a fresh one is
    // a page-faulting allocation of several MB per image. Every element used below is written before it is read.
    thread_local std::vector<Lanes> buf;
    detail::growScratch(buf, size_t(stride) * size_t(H + 2));
    std::fill_n(buf.begin(), stride, far_v);                              // top border
    std::fill_n(buf.begin() + ptrdiff_t(H + 1) * stride, stride, far_v);  // bottom border
    // Each row is initialised just before the forward pass reaches it, and converted to distances as soon as the
    // backward pass has finished it: two sweeps over the buffer instead of four.
    for (int y = 1; y <= H; ++y)  // forward: up-left, up, up-right, left
    {
        Lanes* row = &buf[size_t(y) * size_t(stride)];
        initLanes(class_bits.ptr<uint8_t>(y - 1), W, far_v, row);
        const Lanes* up = row - stride;
        Lanes left = row[0];
        for (int x = 1; x <= W; ++x)
        {
            // The row above first: only the last min waits for the pixel to the left (the pass is bound by that
            // chain, one add and one min per pixel).
            const Lanes v = vmin(vmin(row[x], up[x] + a), vmin(up[x - 1] + d, up[x + 1] + d));
            row[x] = left = vmin(v, left + a);
        }
    }
    distance.resize(size_t(classes));
    for (auto& m : distance) m.create(H, W, CV_32FC1);
    const float inv_s = float(1.0 / s), truncation = float(truncation_px);
    std::vector<float*> out(static_cast<size_t>(classes), nullptr);
    for (int y = H; y >= 1; --y)  // backward: down-right, down, down-left, right
    {
        Lanes* row = &buf[size_t(y) * size_t(stride)];
        const Lanes* down = row + stride;
        Lanes right = row[W + 1];
        for (int x = W; x >= 1; --x)
        {
            const Lanes v = vmin(vmin(row[x], down[x] + a), vmin(down[x + 1] + d, down[x - 1] + d));
            row[x] = right = vmin(v, right + a);
        }
        for (int k = 0; k < classes; ++k) out[size_t(k)] = distance[size_t(k)].ptr<float>(y - 1);
        int x = 0;
        for (; x + 8 <= W; x += 8) storeEightPixels(row + 1 + x, classes, inv_s, truncation, out.data(), x);
        for (; x < W; ++x)
            for (int k = 0; k < classes; ++k) out[size_t(k)][x] = lanePixels(row[1 + x][k], inv_s, truncation);
    }
}

namespace
{
/** One level of the camera side from its (pyramid) image. */
CameraEdgeLevel buildCameraEdgeLevel(const DirectAlignmentOptions& o, const cv::Mat& level_img, int level)
{
    CameraEdgeLevel L;
    L.scale = 1.0 / double(1 << level);
    // Texture (carpet, posters, foliage) makes fine edges everywhere that the LiDAR map does not have; a blur
    // keeps the object boundaries both modalities share.
    cv::Mat edge_img = level_img;
    if (o.camera_blur_sigma_px > 0) cv::GaussianBlur(level_img, edge_img, cv::Size(0, 0), o.camera_blur_sigma_px);
    cv::Mat dx, dy;
    cv::Sobel(edge_img, dx, CV_16S, 1, 0, 3);
    cv::Sobel(edge_img, dy, CV_16S, 0, 1, 3);
    cannyByPercentile(dx, dy, o.canny_high_percentile, o.canny_low_ratio, L.edges);
    // Each edge pixel joins the two orientation classes nearest to its normal's direction (bit b: class b).
    const int B = o.orientation_bins;
    const OrientationClasses orientation(B);
    const bool fused = B <= kMaxFusedClasses;
    cv::Mat class_bits(L.edges.size(), fused ? CV_8UC1 : CV_16UC1, cv::Scalar(0));
    std::vector<int> xs;
    std::vector<float> row_gx, row_gy;
    std::vector<uint8_t> row_bits;
    for (int y = 0; y < L.edges.rows; ++y)
    {
        const uint8_t* edge = L.edges.ptr<uint8_t>(y);
        const int16_t *gx = dx.ptr<int16_t>(y), *gy = dy.ptr<int16_t>(y);
        if (fused)  // B <= 8: a byte per pixel, the row's edge pixels classified four at a time
        {
            xs.clear();
            row_gx.clear();
            row_gy.clear();
            forEachNonZero(edge, L.edges.cols, [&](int x) {
                xs.push_back(x);
                row_gx.push_back(float(gx[x]));
                row_gy.push_back(float(gy[x]));
            });
            row_bits.resize(xs.size());
            orientation.pairBits(row_gx.data(), row_gy.data(), xs.size(), row_bits.data());  // the map side's classes
            uint8_t* bits = class_bits.ptr<uint8_t>(y);
            for (size_t i = 0; i < xs.size(); ++i) bits[xs[i]] = row_bits[i];
            continue;
        }
        uint16_t* bits = class_bits.ptr<uint16_t>(y);
        forEachNonZero(edge, L.edges.cols, [&](int x) {
            int second = 0;
            const int b = orientation.classOf(float(gx[x]), float(gy[x]), &second);  // the map side's classes
            bits[x] = uint16_t((1u << b) | (1u << second));
        });
    }
    // The distance transforms are most of the camera side's cost: up to 8 classes in one fused pass.
    if (fused)
        classDistanceTransforms(class_bits, B, o.truncation_px, L.distance);
    else
    {
        L.distance.resize(size_t(B));
        for (int b = 0; b < B; ++b)
        {
            cv::Mat not_in_class;
            cv::compare(class_bits & cv::Scalar(1 << b), 0, not_in_class, cv::CMP_EQ);
            cv::distanceTransform(not_in_class, L.distance[size_t(b)], cv::DIST_L2, cv::DIST_MASK_3, CV_32F);
            cv::min(L.distance[size_t(b)], o.truncation_px, L.distance[size_t(b)]);
        }
    }
    return L;
}
}  // namespace

CameraEdgeField buildCameraEdgeField(const DirectAlignmentOptions& o, const cv::Mat& image)
{
    core::require(!image.empty() && image.depth() == CV_8U && (image.channels() == 1 || image.channels() == 3),
                  "camera image", "must be a non-empty 8-bit gray or BGR image");
    cv::Mat gray = image;
    if (image.channels() == 3) cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
    CameraEdgeField field;
    cv::GaussianBlur(gray, field.gray, cv::Size(3, 3), 0);
    std::vector<cv::Mat> pyramid{field.gray};
    for (int l = 1; l <= o.pyramid_levels; ++l)
    {
        if (pyramid.back().cols < 32 || pyramid.back().rows < 16) break;  // no smaller levels than this
        cv::Mat down;
        cv::pyrDown(pyramid.back(), down);
        pyramid.push_back(down);
    }
    // The full-resolution level is about three quarters of the work: it runs beside the smaller ones, on two
    // threads when the pool has a free one (the tracker computes the field while it renders the map).
    field.levels.resize(pyramid.size());
    cv::parallel_for_(cv::Range(0, 2), [&](const cv::Range& r) {
        for (int part = r.start; part < r.end; ++part)
            for (size_t l = part == 0 ? 0 : 1; l < (part == 0 ? 1 : pyramid.size()); ++l)
                field.levels[l] = buildCameraEdgeLevel(o, pyramid[l], int(l));
    });
    return field;
}

}  // namespace quasiloc::estimation
