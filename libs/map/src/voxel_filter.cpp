// Voxel-grid downsampling by sorting 64-bit voxel keys: no hash map, cache-friendly, deterministic order.
#include <algorithm>
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/map/map_import.h>

namespace quasiloc::map
{
LidarMap voxelDownsample(const LidarMap& map, double voxel_size_m)
{
    core::require(voxel_size_m > 0 && std::isfinite(voxel_size_m), "voxel_size_m", "must be > 0");
    const size_t n = map.size();
    if (n == 0) return LidarMap();
    const float* P[3] = {map.xs(), map.ys(), map.zs()};
    const double inv = 1.0 / voxel_size_m;
    // Voxel indices relative to the lowest occupied voxel, 21 bits per axis.
    int64_t lo[3];
    for (int a = 0; a < 3; ++a)
    {
        const auto [mn, mx] = std::minmax_element(P[a], P[a] + n);
        lo[a] = static_cast<int64_t>(std::floor(*mn * inv));
        const int64_t span = static_cast<int64_t>(std::floor(*mx * inv)) - lo[a];
        core::require(
            span < (int64_t(1) << 21), "voxel_size_m",
            "too small for the cloud's extent (" + std::to_string(span) + " voxels along one axis, max 2^21)");
    }
    std::vector<std::pair<uint64_t, uint32_t>> keyed(n);
    for (size_t i = 0; i < n; ++i)
    {
        uint64_t key = 0;
        for (int a = 0; a < 3; ++a)
            key = (key << 21) | static_cast<uint64_t>(static_cast<int64_t>(std::floor(P[a][i] * inv)) - lo[a]);
        keyed[i] = {key, static_cast<uint32_t>(i)};
    }
    std::sort(keyed.begin(), keyed.end());

    LidarMap out;
    const float* R = map.reflectivities();
    for (size_t b = 0; b < n;)
    {
        size_t e = b;
        double sum[4] = {0, 0, 0, 0};
        for (; e < n && keyed[e].first == keyed[b].first; ++e)
        {
            const uint32_t i = keyed[e].second;
            sum[0] += P[0][i];
            sum[1] += P[1][i];
            sum[2] += P[2][i];
            sum[3] += R[i];
        }
        const double c = static_cast<double>(e - b);
        out.addPoint(static_cast<float>(sum[0] / c), static_cast<float>(sum[1] / c), static_cast<float>(sum[2] / c),
                     static_cast<float>(sum[3] / c));
        b = e;
    }
    return out;
}

}  // namespace quasiloc::map
