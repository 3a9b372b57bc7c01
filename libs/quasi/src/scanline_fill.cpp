// Scan-line gap filling (render_stages.h, QuasiOptions::scanline_gap_px).
#include "render_stages.h"

#include <algorithm>
#include <cmath>

namespace quasiloc::quasi::detail
{
size_t fillScanlineGapColumns(QuasiImage& out, int x0, int x1, int max_gap_px, double depth_rel)
{
    const int H = out.depth.rows;
    size_t filled = 0;
    for (int x = x0; x < x1; ++x)
    {
        int above = -1;  // the last valid row seen in this column
        for (int y = 0; y < H; ++y)
        {
            if (!out.valid.at<uint8_t>(y, x)) continue;
            const int gap = y - above - 1;
            if (above >= 0 && gap >= 1 && gap <= max_gap_px)
            {
                const float da = out.depth.at<float>(above, x), db = out.depth.at<float>(y, x);
                // Only within one surface: across a depth step the gap is a real occlusion boundary.
                if (std::abs(da - db) <= depth_rel * std::min(da, db))
                {
                    const float ia = out.reflectivity.at<float>(above, x), ib = out.reflectivity.at<float>(y, x);
                    const int32_t pa = out.provenance.at<int32_t>(above, x), pb = out.provenance.at<int32_t>(y, x);
                    for (int g = above + 1; g < y; ++g)
                    {
                        const float t = float(g - above) / float(y - above);
                        out.depth.at<float>(g, x) = 1.f / ((1 - t) / da + t / db);
                        out.reflectivity.at<float>(g, x) = (1 - t) * ia + t * ib;
                        out.provenance.at<int32_t>(g, x) = t <= 0.5f ? pa : pb;
                        out.valid.at<uint8_t>(g, x) = 255;
                    }
                    filled += size_t(gap);
                }
            }
            above = y;
        }
    }
    return filled;
}

}  // namespace quasiloc::quasi::detail
