// Splatting: each map point covers the pixels its footprint spans at its range, not just the pixel its centre
// falls in. A voxelised map seen from close by otherwise leaves holes between its points (a 5 cm voxel at 3 m
// spans 12 px of a 720 px-focal camera) through which farther surfaces show.
#include <algorithm>
#include <cmath>

#include "render_stages.h"

namespace quasiloc::quasi::detail
{
size_t splatRows(const SparsePlanes& src, int y0, int y1, float radius_px_at_1m, int max_radius_px, SparsePlanes& dst)
{
    const int W = src.depth.cols, H = src.depth.rows;
    size_t covered = 0;
    const int ys_begin = std::max(0, y0 - max_radius_px), ys_end = std::min(H, y1 + max_radius_px);
    for (int ys = ys_begin; ys < ys_end; ++ys)
    {
        const float* zs = src.depth.ptr<float>(ys);
        const float* is = src.refl.ptr<float>(ys);
        const int32_t* ms = src.index.ptr<int32_t>(ys);
        for (int xs = 0; xs < W; ++xs)
        {
            const float z = zs[xs];
            if (!(z < kNoDepth)) continue;
            const int r = std::min(max_radius_px, int(radius_px_at_1m / z));
            if (r <= 0 || ys + r < y0 || ys - r >= y1) continue;
            const int ya = std::max(y0, ys - r), yb = std::min(y1, ys + r + 1);
            const int xa = std::max(0, xs - r), xb = std::min(W, xs + r + 1);
            for (int y = ya; y < yb; ++y)
            {
                float* zd = dst.depth.ptr<float>(y);
                float* id = dst.refl.ptr<float>(y);
                int32_t* md = dst.index.ptr<int32_t>(y);
                for (int x = xa; x < xb; ++x)
                {
                    // The nearer point wins; equal depths go to the smaller map index, so the image does not
                    // depend on the order (or the threads) in which the splats are drawn.
                    const bool wins = z < zd[x] || (z == zd[x] && uint32_t(ms[xs]) < uint32_t(md[x]));
                    if (!wins) continue;
                    covered += !(zd[x] < kNoDepth);
                    zd[x] = z;
                    id[x] = is[xs];
                    md[x] = ms[xs];
                }
            }
        }
    }
    return covered;
}

}  // namespace quasiloc::quasi::detail
