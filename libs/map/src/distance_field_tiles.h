#pragma once
// One tile of a brick-stored distance field (the sparse and the streamed layouts of distance_field.h): kTile^3 bricks
// of kBrick^3 voxels, transformed on a buffer with an apron of `reach` voxels on every side. A distance up to the
// truncation comes from an occupied voxel at most `reach` voxels away, which the apron holds, so every stored value
// is the dense grid's to the bit, whichever layout builds the tile and whatever else it has built.
#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "distance_field_detail.h"

namespace quasiloc::map::detail
{
constexpr int kBrick = 16, kBrickVoxels = kBrick * kBrick * kBrick;
constexpr int kTile = 8;  ///< bricks per tile side: a 128^3-voxel core (the apron costs 1.8x its volume)
constexpr int kTileBricks = kTile * kTile * kTile;

/** The field's lattice, as a tile builder needs it. */
struct TileGrid
{
    Eigen::Vector3f origin{0, 0, 0};
    float voxel = 1, max_distance = 0, step = 0;
    Eigen::Vector3i voxels{0, 0, 0}, bricks{0, 0, 0};
    int reach = 1, brick_reach = 1;  ///< voxels (and bricks) within which an occupied voxel matters

    TileGrid() = default;
    TileGrid(const Eigen::Vector3f& origin_, float voxel_, float max_distance_, const Eigen::Vector3i& voxels_)
        : origin(origin_), voxel(voxel_), max_distance(max_distance_), step(max_distance_ / 65535.f), voxels(voxels_)
    {
        bricks = (voxels.array() + kBrick - 1) / kBrick;
        reach = int(std::ceil(max_distance / voxel)) + 1;
        brick_reach = (reach + kBrick - 1) / kBrick;  // reach >= 1 also covers the refinement's neighbours
    }
    Eigen::Vector3i tiles() const { return (bricks.array() + kTile - 1) / kTile; }
    size_t brickIndex(const Eigen::Vector3i& b) const
    {
        return (size_t(b.z()) * size_t(bricks.y()) + size_t(b.y())) * size_t(bricks.x()) + size_t(b.x());
    }
    size_t tileIndex(const Eigen::Vector3i& t) const
    {
        const Eigen::Vector3i n = tiles();
        return (size_t(t.z()) * size_t(n.y()) + size_t(t.y())) * size_t(n.x()) + size_t(t.x());
    }
    Eigen::Vector3f grid(const Eigen::Vector3f& p_world) const { return (p_world - origin) / voxel; }
    static Eigen::Vector3i nearestVoxel(const Eigen::Vector3f& g)
    {
        return {int(std::lround(g.x())), int(std::lround(g.y())), int(std::lround(g.z()))};
    }
    uint16_t quantize(float d) const { return uint16_t(std::lround(std::min(d, max_distance) / step)); }
};

/** A tile's kept bricks: (index of the brick in the tile, x fastest; its kBrickVoxels values), in brick order. */
using TileBricks = std::vector<std::pair<int, std::vector<uint16_t>>>;

struct TileBuffers
{
    std::vector<float> buffer, near;  ///< the padded box's transform, the core's exact near distances
    std::vector<char> occupied;       ///< bricks of the tile and brick_reach around it that hold a point
};

/** Builds the tile whose first brick is t0 * kTile. forEachPoint(lo, hi, visit) must call visit(g) (g: the point in
 *  continuous voxel coordinates) for every map point whose nearest voxel lies in the bricks [lo, hi] (inclusive); more
 *  points are harmless. A brick is kept when one of its values is below the truncation. */
template <typename ForEachPoint>
void buildTile(const TileGrid& grid, const Eigen::Vector3i& tile, ForEachPoint&& forEachPoint, TileBuffers& t,
               TileBricks& out)
{
    out.clear();
    const Eigen::Vector3i t0 = tile * kTile, t1 = (t0.array() + kTile).min(grid.bricks.array());
    // Bricks with a point within brick_reach of one of the tile's: the others are at the truncation.
    const Eigen::Vector3i r0 = (t0.array() - grid.brick_reach).max(0),
                          r1 = (t1.array() - 1 + grid.brick_reach).min(grid.bricks.array() - 1);
    const Eigen::Vector3i rn = r1 - r0 + Eigen::Vector3i::Ones();
    const auto regionIndex = [&](const Eigen::Vector3i& b) {
        return (size_t(b.z() - r0.z()) * size_t(rn.y()) + size_t(b.y() - r0.y())) * size_t(rn.x()) +
               size_t(b.x() - r0.x());
    };
    t.occupied.assign(size_t(rn.prod()), 0);
    size_t points = 0;
    forEachPoint(r0, r1, [&](const Eigen::Vector3f& g) {
        const Eigen::Vector3i b = TileGrid::nearestVoxel(g) / kBrick;
        if ((b.array() < r0.array()).any() || (b.array() > r1.array()).any()) return;
        t.occupied[regionIndex(b)] = 1;
        ++points;
    });
    if (points == 0) return;
    std::vector<char> needed(size_t(kTileBricks), 0);
    bool any = false;
    for (int z = t0.z(); z < t1.z(); ++z)
        for (int y = t0.y(); y < t1.y(); ++y)
            for (int x = t0.x(); x < t1.x(); ++x)
            {
                const Eigen::Vector3i b(x, y, z);
                const Eigen::Vector3i lo = (b.array() - grid.brick_reach).max(r0.array()),
                                      hi = (b.array() + grid.brick_reach).min(r1.array());
                bool n = false;
                for (int zz = lo.z(); zz <= hi.z() && !n; ++zz)
                    for (int yy = lo.y(); yy <= hi.y() && !n; ++yy)
                        for (int xx = lo.x(); xx <= hi.x() && !n; ++xx) n = t.occupied[regionIndex({xx, yy, zz})] != 0;
                needed[size_t(((z - t0.z()) * kTile + (y - t0.y())) * kTile + (x - t0.x()))] = n;
                any = any || n;
            }
    if (!any) return;
    // The occupied voxels of the padded box and the points within one voxel of the core, then the transform.
    const Box core{t0 * kBrick, (t1 * kBrick).cwiseMin(grid.voxels)};
    const Box padded{(core.lo.array() - grid.reach).max(0), (core.hi.array() + grid.reach).min(grid.voxels.array())};
    t.buffer.assign(size_t(padded.size().prod()), kFar);
    t.near.assign(size_t(core.size().prod()), kFar);
    forEachPoint(padded.lo / kBrick, (padded.hi.array() - 1).matrix() / kBrick, [&](const Eigen::Vector3f& g) {
        const Eigen::Vector3i v = TileGrid::nearestVoxel(g);
        if (padded.contains(v.x(), v.y(), v.z())) t.buffer[padded.index(v.x(), v.y(), v.z())] = 0.f;
        nearestInNeighbourhood(g, core, t.near);
    });
    transform(t.buffer, padded.size());
    const uint16_t truncated = grid.quantize(grid.max_distance);
    for (int z = t0.z(); z < t1.z(); ++z)
        for (int y = t0.y(); y < t1.y(); ++y)
            for (int x = t0.x(); x < t1.x(); ++x)
            {
                const int in_tile = ((z - t0.z()) * kTile + (y - t0.y())) * kTile + (x - t0.x());
                if (!needed[size_t(in_tile)]) continue;
                const Eigen::Vector3i b(x, y, z);
                std::vector<uint16_t> values(size_t(kBrickVoxels), truncated);
                bool below = false;
                for (int k = 0; k < kBrick; ++k)
                    for (int j = 0; j < kBrick; ++j)
                        for (int i = 0; i < kBrick; ++i)
                        {
                            const Eigen::Vector3i v = b * kBrick + Eigen::Vector3i(i, j, k);
                            if (!core.contains(v.x(), v.y(), v.z())) continue;  // beyond the grid
                            const float d = finalDistance(t.near[core.index(v.x(), v.y(), v.z())],
                                                          t.buffer[padded.index(v.x(), v.y(), v.z())], grid.voxel,
                                                          grid.max_distance);
                            values[size_t((k * kBrick + j) * kBrick + i)] = grid.quantize(d);
                            below = below || d < grid.max_distance;
                        }
                if (below) out.emplace_back(in_tile, std::move(values));
            }
}

}  // namespace quasiloc::map::detail
