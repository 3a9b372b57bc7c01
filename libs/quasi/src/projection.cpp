// Projection of the culled points into per-thread z-buffers, and their merge.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>

#include "render_stages.h"

namespace quasiloc::quasi::detail
{
namespace
{
/** Derivative of the radial map r -> r * (1 + k1 r^2 + k2 r^4 + k3 r^6) (radtan) or
 *  theta -> theta * (1 + k1 th^2 + ... + k4 th^8) (equidistant), as a function of the variable s. */
double radialSlope(const core::CameraModel& c, double s)
{
    const double s2 = s * s;
    if (c.model == core::DistortionModel::RadTan)
        return 1 + s2 * (3 * c.dist[0] + s2 * (5 * c.dist[1] + s2 * 7 * c.dist[4]));
    if (c.model == core::DistortionModel::Equidistant)
        return 1 + s2 * (3 * c.dist[0] + s2 * (5 * c.dist[1] + s2 * (7 * c.dist[2] + s2 * 9 * c.dist[3])));
    return 1;
}
}  // namespace

FastProjector FastProjector::fromCamera(const core::CameraModel& camera)
{
    camera.check("quasi-image camera");
    FastProjector p;
    p.source = camera;
    p.width = camera.width;
    p.height = camera.height;
    p.fx = float(camera.fx);
    p.fy = float(camera.fy);
    p.cx = float(camera.cx);
    p.cy = float(camera.cy);
    p.model = camera.model;
    for (int i = 0; i < 5; ++i) p.k[i] = float(camera.dist[i]);

    // Box of the undistorted image border (every border pixel edge), widened by 2 px.
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    const double W = camera.width - 0.5, H = camera.height - 0.5;
    auto add = [&](double u, double v) {
        const Eigen::Vector3d r = camera.unproject({u, v});
        if (!std::isfinite(r.x()) || !std::isfinite(r.y())) return;
        lo[0] = std::min(lo[0], r.x());
        lo[1] = std::min(lo[1], r.y());
        hi[0] = std::max(hi[0], r.x());
        hi[1] = std::max(hi[1], r.y());
    };
    for (int u = 0; u <= camera.width; ++u) add(u - 0.5, -0.5), add(u - 0.5, H);
    for (int v = 0; v <= camera.height; ++v) add(-0.5, v - 0.5), add(W, v - 0.5);
    core::require(lo[0] < hi[0] && lo[1] < hi[1], "quasi-image camera",
                  "the image border cannot be undistorted (distortion coefficients unusable)");
    const double mx = 2.0 / camera.fx, my = 2.0 / camera.fy;
    p.xn_min = float(lo[0] - mx);
    p.xn_max = float(hi[0] + mx);
    p.yn_min = float(lo[1] - my);
    p.yn_max = float(hi[1] + my);

    // Where the radial polynomial stops increasing, points beyond would fold back into the image.
    if (camera.model != core::DistortionModel::None)
    {
        const double r_corner = std::hypot(std::max(-lo[0], hi[0]) + mx, std::max(-lo[1], hi[1]) + my);
        const bool equi = camera.model == core::DistortionModel::Equidistant;
        const double s_end = equi ? std::atan(r_corner) : r_corner;
        constexpr int kSteps = 2000;
        for (int i = 1; i <= kSteps; ++i)
        {
            const double s = s_end * i / kSteps;
            if (radialSlope(camera, s) <= 0)
            {
                const double s_fold = s_end * (i - 1) / kSteps;
                const double r_fold = equi ? std::tan(s_fold) : s_fold;
                p.r2_max = float(r_fold * r_fold);
                break;
            }
        }
    }
    return p;
}

bool FastProjector::sameCamera(const core::CameraModel& c) const
{
    const core::CameraModel& s = source;
    return c.width == s.width && c.height == s.height && c.fx == s.fx && c.fy == s.fy && c.cx == s.cx && c.cy == s.cy &&
           c.model == s.model && c.dist == s.dist;
}

PoseF PoseF::camFromWorld(const mrpt::poses::CPose3D& T_world_cam)
{
    core::checkFinite(T_world_cam, "quasi-image pose T_world_cam");
    // Inverse in double, then one rounding to float: two chains giving the same pose to ~1e-16 give the
    // same floats, hence the same image.
    const mrpt::poses::CPose3D T_cam_world = -T_world_cam;
    const auto& R = T_cam_world.getRotationMatrix();
    PoseF p;
    for (int r = 0; r < 3; ++r)
    {
        for (int c = 0; c < 3; ++c) p.R[3 * r + c] = float(R(r, c));
        p.t[r] = float(T_cam_world.m_coords[r]);
    }
    return p;
}

void SparsePlanes::create(int width, int height, int margin_px)
{
    margin = margin_px;
    const cv::Rect inner(margin, margin, width, height);
    const int W = width + 2 * margin, H = height + 2 * margin;
    depth = cv::Mat(H, W, CV_32FC1, cv::Scalar(kNoDepth))(inner);
    refl = cv::Mat(H, W, CV_32FC1, cv::Scalar(0))(inner);
    index = cv::Mat(H, W, CV_32SC1, cv::Scalar(-1))(inner);
}

namespace
{
constexpr int kBatch = 256;

/** Phase A of the projection of one batch, free of branches so that the compiler vectorises it: the pixel
 *  of each point (-1: rejected) and its depth. Templated on the distortion model to keep the loop tight. */
template <core::DistortionModel Model>
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
// Vectorised for AVX2 too, chosen at run time (the default clone is plain x86-64: SSE2).
__attribute__((target_clones("avx2", "default")))
#endif
void projectBatch(const float* X, const float* Y, const float* Z, int m, const FastProjector& cam,
                  const PoseF& pose, float min_depth, float max_depth, int32_t pix_begin, int32_t pix_end,
                  int32_t* pix, float* depth)
{
    const float r0 = pose.R[0], r1 = pose.R[1], r2c = pose.R[2], r3 = pose.R[3], r4 = pose.R[4], r5 = pose.R[5];
    const float r6 = pose.R[6], r7 = pose.R[7], r8 = pose.R[8], t0 = pose.t[0], t1 = pose.t[1], t2 = pose.t[2];
    // RadTan: d = (k1, k2, p1, p2, k3); Equidistant: d = (k1, k2, k3, k4, -).
    const float d0 = cam.k[0], d1 = cam.k[1], d2 = cam.k[2], d3 = cam.k[3], d4 = cam.k[4];
    const float W = float(cam.width), H = float(cam.height);
    const int width = cam.width;
    for (int j = 0; j < m; ++j)
    {
        const float px = X[j], py = Y[j], pz = Z[j];
        const float z = r6 * px + r7 * py + r8 * pz + t2;
        const bool z_ok = (z >= min_depth) & (z <= max_depth);
        const float iz = 1.0f / (z_ok ? z : 1.0f);
        const float xn = (r0 * px + r1 * py + r2c * pz + t0) * iz;
        const float yn = (r3 * px + r4 * py + r5 * pz + t1) * iz;
        const float rr = xn * xn + yn * yn;
        bool ok = z_ok & (xn >= cam.xn_min) & (xn <= cam.xn_max) & (yn >= cam.yn_min) & (yn <= cam.yn_max) &
                  (rr <= cam.r2_max);
        float xd = xn, yd = yn;
        if constexpr (Model == core::DistortionModel::RadTan)
        {
            const float radial = 1.0f + rr * (d0 + rr * (d1 + rr * d4));
            xd = xn * radial + 2.0f * d2 * xn * yn + d3 * (rr + 2.0f * xn * xn);
            yd = yn * radial + d2 * (rr + 2.0f * yn * yn) + 2.0f * d3 * xn * yn;
        }
        else if constexpr (Model == core::DistortionModel::Equidistant)
        {
            const float r = std::sqrt(rr);
            const float th = std::atan(r), th2 = th * th;
            const float s = r > 1e-10f ? th * (1.0f + th2 * (d0 + th2 * (d1 + th2 * (d2 + th2 * d3)))) / r : 1.0f;
            xd = xn * s;
            yd = yn * s;
        }
        // Pixel (i, j) covers [i - 0.5, i + 0.5): floor(u + 0.5).
        const float u = cam.fx * xd + cam.cx + 0.5f, v = cam.fy * yd + cam.cy + 0.5f;
        ok = ok & (u >= 0.0f) & (v >= 0.0f) & (u < W) & (v < H);
        const int iu = int(ok ? u : 0.0f), iv = int(ok ? v : 0.0f);
        const int p = iv * width + iu;
        pix[j] = (ok & (p >= pix_begin) & (p < pix_end)) ? p : -1;
        depth[j] = z;
    }
}

/** Phase B of one batch: the z-buffer test of the points with pix >= 0, branch-free (which of two points wins
 *  a pixel is unpredictable, and a mispredicted branch would serialise the cache misses on the z-buffer), with
 *  the slots prefetched. M, I: the batch's map indices and reflectivities. Returns the points tested. */
size_t zTestBatch(const int32_t* pix, const float* depth, int m, const uint32_t* M, const float* I, ZBuffer& zb)
{
    uint64_t* key = zb.key.data();
    float* refl = zb.refl.data();
    size_t projected = 0;
    constexpr int kAhead = 16;
    for (int j = 0; j < std::min(m, kAhead); ++j)
        if (pix[j] >= 0) __builtin_prefetch(&key[pix[j]], 1);
    for (int j = 0; j < m; ++j)
    {
        if (j + kAhead < m && pix[j + kAhead] >= 0) __builtin_prefetch(&key[pix[j + kAhead]], 1);
        if (pix[j] < 0) continue;
        uint32_t zbits, rnew, rold;
        std::memcpy(&zbits, &depth[j], sizeof zbits);
        const uint64_t kk = (uint64_t(zbits) << 32) | M[j];
        const uint64_t old = key[pix[j]];
        const uint64_t win = uint64_t(0) - uint64_t(kk < old);  // all ones when the point wins
        key[pix[j]] = (kk & win) | (old & ~win);
        std::memcpy(&rnew, &I[j], sizeof rnew);
        std::memcpy(&rold, &refl[pix[j]], sizeof rold);
        const uint32_t r = (rnew & uint32_t(win)) | (rold & ~uint32_t(win));
        std::memcpy(&refl[pix[j]], &r, sizeof r);
        ++projected;
    }
    return projected;
}

template <core::DistortionModel Model>
size_t projectRun(const map::VisibilityIndex& index, size_t k_begin, size_t k_end, const FastProjector& cam,
                  const PoseF& pose, float min_depth, float max_depth, int32_t pix_begin, int32_t pix_end, ZBuffer& zb)
{
    alignas(64) int32_t pix[kBatch];
    alignas(64) float depth[kBatch];
    size_t projected = 0;
    for (size_t k0 = k_begin; k0 < k_end; k0 += kBatch)
    {
        const int m = int(std::min<size_t>(kBatch, k_end - k0));
        projectBatch<Model>(index.xs() + k0, index.ys() + k0, index.zs() + k0, m, cam, pose, min_depth, max_depth,
                            pix_begin, pix_end, pix, depth);
        projected += zTestBatch(pix, depth, m, index.mapIndex() + k0, index.reflectivities() + k0, zb);
    }
    return projected;
}

/** Calls f(k_begin, k_end, position) for the pieces of `ranges` within [first, last) of their concatenation
 *  (position: where the piece starts in the concatenation). */
template <class F>
void forRangePieces(const std::vector<map::VisibilityIndex::Range>& ranges, size_t first, size_t last, F&& f)
{
    size_t offset = 0;
    for (const auto& rg : ranges)
    {
        const size_t n = rg.end - rg.begin;
        const size_t a = std::max(first, offset), b = std::min(last, offset + n);
        if (a < b) f(rg.begin + (a - offset), rg.begin + (b - offset), a);
        offset += n;
    }
}
}  // namespace

void projectPoints(const map::VisibilityIndex& index, const std::vector<map::VisibilityIndex::Range>& ranges,
                   size_t first, size_t last, const FastProjector& cam, const PoseF& pose, float min_depth,
                   float max_depth, ZBuffer& zb)
{
    zb.projected =
        projectPoints(index, ranges, first, last, cam, pose, min_depth, max_depth, 0, cam.width * cam.height, zb);
}

size_t projectPoints(const map::VisibilityIndex& index, const std::vector<map::VisibilityIndex::Range>& ranges,
                     size_t first, size_t last, const FastProjector& cam, const PoseF& pose, float min_depth,
                     float max_depth, int32_t pix_begin, int32_t pix_end, ZBuffer& zb)
{
    size_t projected = 0;
    forRangePieces(ranges, first, last, [&](size_t k_begin, size_t k_end, size_t) {
        switch (cam.model)
        {
            case core::DistortionModel::None:
                projected += projectRun<core::DistortionModel::None>(index, k_begin, k_end, cam, pose, min_depth,
                                                                     max_depth, pix_begin, pix_end, zb);
                break;
            case core::DistortionModel::RadTan:
                projected += projectRun<core::DistortionModel::RadTan>(index, k_begin, k_end, cam, pose, min_depth,
                                                                       max_depth, pix_begin, pix_end, zb);
                break;
            case core::DistortionModel::Equidistant:
                projected += projectRun<core::DistortionModel::Equidistant>(index, k_begin, k_end, cam, pose, min_depth,
                                                                            max_depth, pix_begin, pix_end, zb);
                break;
        }
    });
    return projected;
}

void projectToBuffer(const map::VisibilityIndex& index, const std::vector<map::VisibilityIndex::Range>& ranges,
                     size_t first, size_t last, const FastProjector& cam, const PoseF& pose, float min_depth,
                     float max_depth, int32_t* pix, float* depth)
{
    const int32_t n_pix = cam.width * cam.height;
    forRangePieces(ranges, first, last, [&](size_t k_begin, size_t k_end, size_t pos) {
        for (size_t k0 = k_begin; k0 < k_end; k0 += kBatch)
        {
            const int m = int(std::min<size_t>(kBatch, k_end - k0));
            const size_t at = pos + (k0 - k_begin);
            const float *X = index.xs() + k0, *Y = index.ys() + k0, *Z = index.zs() + k0;
            switch (cam.model)
            {
                case core::DistortionModel::None:
                    projectBatch<core::DistortionModel::None>(X, Y, Z, m, cam, pose, min_depth, max_depth, 0, n_pix,
                                                              pix + at, depth + at);
                    break;
                case core::DistortionModel::RadTan:
                    projectBatch<core::DistortionModel::RadTan>(X, Y, Z, m, cam, pose, min_depth, max_depth, 0, n_pix,
                                                                pix + at, depth + at);
                    break;
                case core::DistortionModel::Equidistant:
                    projectBatch<core::DistortionModel::Equidistant>(X, Y, Z, m, cam, pose, min_depth, max_depth, 0,
                                                                     n_pix, pix + at, depth + at);
                    break;
            }
        }
    });
}

size_t zTestBuffer(const map::VisibilityIndex& index, const std::vector<map::VisibilityIndex::Range>& ranges,
                   const int32_t* pix, const float* depth, int32_t pix_begin, int32_t pix_end, ZBuffer& zb)
{
    size_t projected = 0;
    alignas(64) int32_t band[kBatch];
    forRangePieces(ranges, 0, map::VisibilityIndex::countPoints(ranges), [&](size_t k_begin, size_t k_end, size_t pos) {
        for (size_t k0 = k_begin; k0 < k_end; k0 += kBatch)
        {
            const int m = int(std::min<size_t>(kBatch, k_end - k0));
            const size_t at = pos + (k0 - k_begin);
            for (int j = 0; j < m; ++j)
            {
                const int32_t p = pix[at + j];
                band[j] = (p >= pix_begin) & (p < pix_end) ? p : -1;
            }
            projected += zTestBatch(band, depth + at, m, index.mapIndex() + k0, index.reflectivities() + k0, zb);
        }
    });
    return projected;
}

namespace
{
/** zb0 = per-pixel minimum of zb0 and zb (keys and their reflectivity); zb is reset to empty. Plain loops
 *  over a row that the compiler vectorises. */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
void mergeRowInto(uint64_t* __restrict key0, float* __restrict refl0, uint64_t* __restrict key, const float* refl,
                  int n)
{
    for (int x = 0; x < n; ++x)
    {
        const uint64_t k = key[x], best = key0[x];
        const bool lt = k < best;
        refl0[x] = lt ? refl[x] : refl0[x];
        key0[x] = lt ? k : best;
        key[x] = kEmptyKey;
    }
}

/** The winning keys of a row -> sparse planes; the keys are reset to empty (no separate clearing pass). */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
void unpackRow(uint64_t* __restrict key, const float* __restrict refl_in, float* __restrict depth,
               float* __restrict refl, int32_t* __restrict index, int n)
{
    const uint32_t no_depth = 0x7f800000u;  // +inf
    for (int x = 0; x < n; ++x)
    {
        const uint64_t k = key[x];
        const bool empty = k == kEmptyKey;
        const uint32_t zbits = empty ? no_depth : uint32_t(k >> 32);
        std::memcpy(&depth[x], &zbits, sizeof zbits);
        refl[x] = empty ? 0.0f : refl_in[x];
        index[x] = empty ? -1 : int32_t(uint32_t(k));
        key[x] = kEmptyKey;
    }
}
}  // namespace

void mergeZBuffers(std::vector<ZBuffer>& zbs, int y0, int y1, SparsePlanes& sparse)
{
    const int width = sparse.depth.cols;
    for (int y = y0; y < y1; ++y)
    {
        const size_t row = size_t(y) * width;
        // The minimum over all z-buffers collects in the first (in order: the result does not depend on which
        // thread filled which buffer, as keys are unique).
        for (size_t s = 1; s < zbs.size(); ++s)
            mergeRowInto(zbs[0].key.data() + row, zbs[0].refl.data() + row, zbs[s].key.data() + row,
                         zbs[s].refl.data() + row, width);
        unpackRow(zbs[0].key.data() + row, zbs[0].refl.data() + row, sparse.depth.ptr<float>(y),
                  sparse.refl.ptr<float>(y), sparse.index.ptr<int32_t>(y), width);
    }
}

}  // namespace quasiloc::quasi::detail
