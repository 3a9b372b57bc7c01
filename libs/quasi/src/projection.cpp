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
    return c.width == s.width && c.height == s.height && c.fx == s.fx && c.fy == s.fy && c.cx == s.cx &&
           c.cy == s.cy && c.model == s.model && c.dist == s.dist;
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

void SparsePlanes::create(int width, int height)
{
    depth.create(height, width, CV_32FC1);
    refl.create(height, width, CV_32FC1);
    index.create(height, width, CV_32SC1);
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
                  const PoseF& pose, float min_depth, float max_depth, int32_t* pix, float* depth)
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
        pix[j] = ok ? iv * width + iu : -1;
        depth[j] = z;
    }
}

template <core::DistortionModel Model>
size_t projectRun(const map::VisibilityIndex& index, size_t k_begin, size_t k_end, const FastProjector& cam,
                  const PoseF& pose, float min_depth, float max_depth, ZBuffer& zb)
{
    alignas(64) int32_t pix[kBatch];
    alignas(64) float depth[kBatch];
    const float* I = index.reflectivities();
    const uint32_t* M = index.mapIndex();
    uint64_t* key = zb.key.data();
    float* refl = zb.refl.data();
    size_t projected = 0;
    for (size_t k0 = k_begin; k0 < k_end; k0 += kBatch)
    {
        const int m = int(std::min<size_t>(kBatch, k_end - k0));
        projectBatch<Model>(index.xs() + k0, index.ys() + k0, index.zs() + k0, m, cam, pose, min_depth, max_depth,
                            pix, depth);
        // Phase B: the z-buffer test, branch-free (which of two points wins a pixel is unpredictable, and a
        // mispredicted branch would serialise the cache misses on the z-buffer), with the slots prefetched.
        constexpr int kAhead = 16;
        for (int j = 0; j < std::min(m, kAhead); ++j)
            if (pix[j] >= 0) __builtin_prefetch(&key[pix[j]], 1);
        for (int j = 0; j < m; ++j)
        {
            if (j + kAhead < m && pix[j + kAhead] >= 0) __builtin_prefetch(&key[pix[j + kAhead]], 1);
            if (pix[j] < 0) continue;
            uint32_t zbits, rnew, rold;
            std::memcpy(&zbits, &depth[j], sizeof zbits);
            const uint64_t kk = (uint64_t(zbits) << 32) | M[k0 + j];
            const uint64_t old = key[pix[j]];
            const uint64_t win = uint64_t(0) - uint64_t(kk < old);  // all ones when the point wins
            key[pix[j]] = (kk & win) | (old & ~win);
            std::memcpy(&rnew, &I[k0 + j], sizeof rnew);
            std::memcpy(&rold, &refl[pix[j]], sizeof rold);
            const uint32_t r = (rnew & uint32_t(win)) | (rold & ~uint32_t(win));
            std::memcpy(&refl[pix[j]], &r, sizeof r);
            ++projected;
        }
    }
    return projected;
}
}  // namespace

void projectPoints(const map::VisibilityIndex& index, const std::vector<map::VisibilityIndex::Range>& ranges,
                   size_t first, size_t last, const FastProjector& cam, const PoseF& pose, float min_depth,
                   float max_depth, ZBuffer& zb)
{
    size_t projected = 0;
    size_t offset = 0;  // position of the current range in the concatenation of all ranges
    for (const auto& rg : ranges)
    {
        const size_t n = rg.end - rg.begin;
        const size_t a = std::max(first, offset), b = std::min(last, offset + n);
        const size_t range_start = offset;
        offset += n;
        if (a >= b) continue;
        const size_t k_begin = rg.begin + (a - range_start), k_end = rg.begin + (b - range_start);
        switch (cam.model)
        {
            case core::DistortionModel::None:
                projected += projectRun<core::DistortionModel::None>(index, k_begin, k_end, cam, pose, min_depth,
                                                                     max_depth, zb);
                break;
            case core::DistortionModel::RadTan:
                projected += projectRun<core::DistortionModel::RadTan>(index, k_begin, k_end, cam, pose, min_depth,
                                                                       max_depth, zb);
                break;
            case core::DistortionModel::Equidistant:
                projected += projectRun<core::DistortionModel::Equidistant>(index, k_begin, k_end, cam, pose,
                                                                            min_depth, max_depth, zb);
                break;
        }
    }
    zb.projected = projected;
}

void mergeZBuffers(std::vector<ZBuffer>& zbs, int y0, int y1, SparsePlanes& sparse)
{
    const int width = sparse.depth.cols;
    for (int y = y0; y < y1; ++y)
    {
        float* depth = sparse.depth.ptr<float>(y);
        float* refl = sparse.refl.ptr<float>(y);
        int32_t* index = sparse.index.ptr<int32_t>(y);
        const size_t row = size_t(y) * width;
        for (int x = 0; x < width; ++x)
        {
            const size_t p = row + x;
            uint64_t best = kEmptyKey;
            float r = 0;
            for (ZBuffer& zb : zbs)
            {
                const uint64_t k = zb.key[p];
                r = k < best ? zb.refl[p] : r;
                best = k < best ? k : best;
                zb.key[p] = kEmptyKey;  // ready for the next image: no separate clearing pass
            }
            if (best == kEmptyKey)
            {
                depth[x] = kNoDepth, refl[x] = 0, index[x] = -1;
                continue;
            }
            const uint32_t zbits = uint32_t(best >> 32);
            std::memcpy(&depth[x], &zbits, sizeof zbits);
            refl[x] = r;
            index[x] = int32_t(uint32_t(best & 0xffffffffu));
        }
    }
}

}  // namespace quasiloc::quasi::detail
