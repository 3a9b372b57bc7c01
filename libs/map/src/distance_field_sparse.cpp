// The sparse DistanceField (distance_field.h): only the bricks within the truncation of a map point are stored.
// Bricks are transformed a tile at a time (kTile^3 bricks) on a buffer that adds an apron of `reach` voxels on every
// side: a distance up to the truncation comes from an occupied voxel at most `reach` voxels away, which the apron
// holds, so every stored value is the dense grid's to the bit.
#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <cmath>
#include <quasiloc/map/distance_field.h>
#include <unordered_map>

#include "distance_field_detail.h"

namespace quasiloc::map
{
namespace
{
using detail::Box;
using detail::kFar;
constexpr int kTile = 8;  ///< bricks per tile side: a 128^3-voxel core (the apron costs 1.8x its volume)

}  // namespace

DistanceField DistanceField::buildSparse(const LidarMap& map, DistanceField f)
{
    f.sparse_ = true;
    f.bx_ = (f.nx_ + kBrick - 1) / kBrick, f.by_ = (f.ny_ + kBrick - 1) / kBrick, f.bz_ = (f.nz_ + kBrick - 1) / kBrick;
    const Eigen::Vector3i grid(f.nx_, f.ny_, f.nz_), bricks(f.bx_, f.by_, f.bz_);
    const auto brickIndex = [&](const Eigen::Vector3i& b) {
        return (size_t(b.z()) * size_t(f.by_) + size_t(b.y())) * size_t(f.bx_) + size_t(b.x());
    };
    // The map's points by the brick of their voxel: a counting sort, 4 bytes per point (not a copy of the points).
    const auto gridOf = [&](size_t n) { return Eigen::Vector3f((map.point(n) - f.origin_) / f.voxel_); };
    const auto brickOf = [&](size_t n) {
        const Eigen::Vector3f g = gridOf(n);
        const Eigen::Vector3i v(int(std::lround(g.x())), int(std::lround(g.y())), int(std::lround(g.z())));
        return brickIndex(v / kBrick);
    };
    std::unordered_map<size_t, std::pair<uint32_t, uint32_t>> points_of_brick;  // brick -> [begin, end) in `order`
    for (size_t n = 0; n < map.size(); ++n) ++points_of_brick[brickOf(n)].second;
    uint32_t start = 0;
    for (auto& [b, r] : points_of_brick) r = {start, start + r.second}, start = r.second;
    std::vector<uint32_t> order(map.size());
    {
        std::unordered_map<size_t, uint32_t> next;
        for (const auto& [b, r] : points_of_brick) next[b] = r.first;
        for (size_t n = 0; n < map.size(); ++n) order[next[brickOf(n)]++] = uint32_t(n);
    }
    // A voxel farther than `reach` from every occupied voxel is at the truncation.
    const int reach = int(std::ceil(f.max_distance_ / f.voxel_)) + 1;
    const int brick_reach = (reach + kBrick - 1) / kBrick;  // reach >= 1 also covers the refinement's neighbours
    f.brick_of_.assign(size_t(f.bx_) * size_t(f.by_) * size_t(f.bz_), -1);
    std::vector<char> needed(f.brick_of_.size(), 0);
    for (const auto& [b, range] : points_of_brick)
    {
        const Eigen::Vector3i c(int(b % size_t(f.bx_)), int(b / size_t(f.bx_) % size_t(f.by_)),
                                int(b / (size_t(f.bx_) * size_t(f.by_))));
        const Eigen::Vector3i lo = (c.array() - brick_reach).max(0),
                              hi = (c.array() + brick_reach).min(bricks.array() - 1);
        for (int z = lo.z(); z <= hi.z(); ++z)
            for (int y = lo.y(); y <= hi.y(); ++y)
                for (int x = lo.x(); x <= hi.x(); ++x) needed[brickIndex({x, y, z})] = 1;
    }
    // One tile's work: the occupied voxels of the padded box and the points within one voxel of the core, the
    // transform, then the final values of its needed bricks (those with a value below the truncation are kept).
    struct TileBuffers
    {
        std::vector<float> buffer, near;  // the padded box's transform, the core's exact near distances
    };
    using Bricks = std::vector<std::pair<size_t, std::vector<uint16_t>>>;  // (brick index, values)
    const auto markPoints = [&](const Box& core, const Box& padded, TileBuffers& t) {
        t.buffer.assign(size_t(padded.size().prod()), kFar);
        t.near.assign(size_t(core.size().prod()), kFar);
        const Eigen::Vector3i b0 = padded.lo / kBrick, b1 = ((padded.hi.array() - 1) / kBrick).matrix();
        for (int z = b0.z(); z <= b1.z(); ++z)
            for (int y = b0.y(); y <= b1.y(); ++y)
                for (int x = b0.x(); x <= b1.x(); ++x)
                {
                    const auto it = points_of_brick.find(brickIndex({x, y, z}));
                    if (it == points_of_brick.end()) continue;
                    for (uint32_t k = it->second.first; k < it->second.second; ++k)
                    {
                        const Eigen::Vector3f g = gridOf(order[k]);
                        const Eigen::Vector3i v(int(std::lround(g.x())), int(std::lround(g.y())),
                                                int(std::lround(g.z())));
                        if (padded.contains(v.x(), v.y(), v.z())) t.buffer[padded.index(v.x(), v.y(), v.z())] = 0.f;
                        detail::nearestInNeighbourhood(g, core, t.near);
                    }
                }
    };
    const auto keepBrick = [&](const Eigen::Vector3i& b, const Box& core, const Box& padded, const TileBuffers& t,
                               Bricks& out) {
        std::vector<uint16_t> values(size_t(kBrickVoxels), f.quantize(f.max_distance_));
        bool below = false;
        for (int k = 0; k < kBrick; ++k)
            for (int j = 0; j < kBrick; ++j)
                for (int i = 0; i < kBrick; ++i)
                {
                    const Eigen::Vector3i v = b * kBrick + Eigen::Vector3i(i, j, k);
                    if (!core.contains(v.x(), v.y(), v.z())) continue;  // beyond the grid
                    const float d =
                        detail::finalDistance(t.near[core.index(v.x(), v.y(), v.z())],
                                              t.buffer[padded.index(v.x(), v.y(), v.z())], f.voxel_, f.max_distance_);
                    values[size_t((k * kBrick + j) * kBrick + i)] = f.quantize(d);
                    below = below || d < f.max_distance_;
                }
        if (below) out.emplace_back(brickIndex(b), std::move(values));
    };
    const auto buildTile = [&](const Eigen::Vector3i& t0, TileBuffers& t, Bricks& out) {
        const Eigen::Vector3i t1 = (t0.array() + kTile).min(bricks.array());
        const Box core{t0 * kBrick, (t1 * kBrick).cwiseMin(grid)};
        const Box padded{(core.lo.array() - reach).max(0), (core.hi.array() + reach).min(grid.array())};
        markPoints(core, padded, t);
        detail::transform(t.buffer, padded.size());
        for (int z = t0.z(); z < t1.z(); ++z)
            for (int y = t0.y(); y < t1.y(); ++y)
                for (int x = t0.x(); x < t1.x(); ++x)
                    if (needed[brickIndex({x, y, z})]) keepBrick({x, y, z}, core, padded, t, out);
    };
    // The tiles with a needed brick, transformed on every core; their bricks are stored in tile order, so the
    // field does not depend on the number of threads.
    std::vector<Eigen::Vector3i> tiles;
    for (int tz = 0; tz < f.bz_; tz += kTile)
        for (int ty = 0; ty < f.by_; ty += kTile)
            for (int tx = 0; tx < f.bx_; tx += kTile)
            {
                const Eigen::Vector3i t0(tx, ty, tz), t1 = (t0.array() + kTile).min(bricks.array());
                bool any = false;
                for (int z = t0.z(); z < t1.z() && !any; ++z)
                    for (int y = t0.y(); y < t1.y() && !any; ++y)
                        for (int x = t0.x(); x < t1.x() && !any; ++x) any = needed[brickIndex({x, y, z})] != 0;
                if (any) tiles.push_back(t0);
            }
    std::vector<Bricks> tile_bricks(tiles.size());
    std::atomic<size_t> next{0};
    std::mutex failure_mutex;
    std::exception_ptr failure;
    const auto work = [&] {
        try
        {
            TileBuffers t;
            for (size_t i = next++; i < tiles.size(); i = next++) buildTile(tiles[i], t, tile_bricks[i]);
        }
        catch (...)
        {
            std::lock_guard<std::mutex> lock(failure_mutex);
            if (!failure) failure = std::current_exception();
            next = tiles.size();
        }
    };
    std::vector<std::thread> pool;
    for (unsigned k = 1; k < std::max(1u, std::thread::hardware_concurrency()); ++k) pool.emplace_back(work);
    work();
    for (auto& th : pool) th.join();
    if (failure) std::rethrow_exception(failure);
    for (Bricks& tb : tile_bricks)
        for (auto& [b, values] : tb)
        {
            f.brick_of_[b] = int(f.bricks_.size());
            f.bricks_.push_back(std::move(values));
        }
    return f;
}

}  // namespace quasiloc::map
