// NearPoints (near_points.h): gather, filter by the query's neighbourhood, group by cell.
#include "near_points.h"

#include <cmath>
#include <unordered_set>

namespace quasiloc::reloc
{
namespace
{
uint64_t cellKey(const Eigen::Vector3f& p, float inv_cell)
{
    const auto u = [&](float v) {
        return uint64_t(uint32_t(int32_t(std::floor(v * inv_cell)) + (1 << 20)) & 0x1FFFFFu);
    };
    return (u(p.x()) << 42) | (u(p.y()) << 21) | u(p.z());
}
uint64_t shifted(uint64_t key, int dx, int dy, int dz)
{
    return key + (uint64_t(int64_t(dx)) << 42) + (uint64_t(int64_t(dy)) << 21) + uint64_t(int64_t(dz));
}
}  // namespace

NearPoints::NearPoints(const map::VisibilityIndex& index, const std::vector<Eigen::Vector3f>& points_world,
                       float reach_m, float cell_m)
    : cell_(cell_m)
{
    if (points_world.empty()) return;
    // The query's neighbourhood: cells of size reach_m holding a query point, and their 26 neighbours.
    const float inv_reach = 1.f / reach_m;
    std::unordered_set<uint64_t> near;
    Eigen::Vector3f lo = points_world.front(), hi = lo;
    for (const Eigen::Vector3f& p : points_world)
    {
        lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
        const uint64_t k = cellKey(p, inv_reach);
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) near.insert(shifted(k, dx, dy, dz));
    }
    std::vector<map::VisibilityIndex::Range> ranges;
    index.queryBox((lo.array() - reach_m).cast<double>(), (hi.array() + reach_m).cast<double>(), ranges);
    std::vector<Eigen::Vector3f> kept;
    for (const auto& r : ranges)
        for (uint32_t k = r.begin; k < r.end; ++k)
        {
            const Eigen::Vector3f p(index.xs()[k], index.ys()[k], index.zs()[k]);
            if (near.count(cellKey(p, inv_reach))) kept.push_back(p);
        }
    // Group by grid cell (a counting sort).
    for (const Eigen::Vector3f& p : kept) ++cells_[key(p)].second;
    uint32_t start = 0;
    std::unordered_map<uint64_t, uint32_t> next;
    for (auto& [k, r] : cells_)
    {
        const uint32_t n = r.second;
        r = {start, start + n};
        next[k] = start;
        start += n;
    }
    points_.resize(kept.size());
    for (const Eigen::Vector3f& p : kept) points_[next[key(p)]++] = p;
}

uint64_t NearPoints::key(const Eigen::Vector3f& p) const { return cellKey(p, 1.f / cell_); }

bool NearPoints::nearest(const Eigen::Vector3f& q, float radius_m, Eigen::Vector3f& point, float& d2) const
{
    const uint64_t k = key(q);
    float best = radius_m * radius_m;
    bool found = false;
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
            {
                const auto it = cells_.find(shifted(k, dx, dy, dz));
                if (it == cells_.end()) continue;
                for (uint32_t i = it->second.first; i < it->second.second; ++i)
                {
                    const float d = (points_[i] - q).squaredNorm();
                    if (d < best) best = d, point = points_[i], found = true;
                }
            }
    d2 = best;
    return found;
}

}  // namespace quasiloc::reloc
