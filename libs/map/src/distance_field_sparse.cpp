// The sparse DistanceField (distance_field.h): only the bricks within the truncation of a map point are stored.
// Bricks are transformed a tile at a time on a buffer with an apron (distance_field_tiles.h), on every core.
#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <cmath>
#include <quasiloc/map/distance_field.h>
#include <unordered_map>

#include "distance_field_tiles.h"

namespace quasiloc::map
{
namespace
{
using detail::kTile;
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
    // The tiles within brick_reach of a brick with points (the others hold no value below the truncation), in
    // index order.
    const detail::TileGrid tg(f.origin_, f.voxel_, f.max_distance_, grid);
    const Eigen::Vector3i tile_count = tg.tiles();
    std::vector<char> tile_needed(size_t(tile_count.prod()), 0);
    for (const auto& [b, range] : points_of_brick)
    {
        const Eigen::Vector3i c(int(b % size_t(f.bx_)), int(b / size_t(f.bx_) % size_t(f.by_)),
                                int(b / (size_t(f.bx_) * size_t(f.by_))));
        const Eigen::Vector3i lo = (c.array() - tg.brick_reach).max(0) / kTile,
                              hi = (c.array() + tg.brick_reach).min(bricks.array() - 1) / kTile;
        for (int z = lo.z(); z <= hi.z(); ++z)
            for (int y = lo.y(); y <= hi.y(); ++y)
                for (int x = lo.x(); x <= hi.x(); ++x) tile_needed[tg.tileIndex({x, y, z})] = 1;
    }
    std::vector<Eigen::Vector3i> tiles;
    for (int z = 0; z < tile_count.z(); ++z)
        for (int y = 0; y < tile_count.y(); ++y)
            for (int x = 0; x < tile_count.x(); ++x)
                if (tile_needed[tg.tileIndex({x, y, z})]) tiles.emplace_back(x, y, z);
    const auto forEachPoint = [&](const Eigen::Vector3i& lo, const Eigen::Vector3i& hi, const auto& visit) {
        for (int z = lo.z(); z <= hi.z(); ++z)
            for (int y = lo.y(); y <= hi.y(); ++y)
                for (int x = lo.x(); x <= hi.x(); ++x)
                {
                    const auto it = points_of_brick.find(brickIndex({x, y, z}));
                    if (it == points_of_brick.end()) continue;
                    for (uint32_t k = it->second.first; k < it->second.second; ++k) visit(gridOf(order[k]));
                }
    };
    using Bricks = detail::TileBricks;
    std::vector<Bricks> tile_bricks(tiles.size());
    std::atomic<size_t> next{0};
    std::mutex failure_mutex;
    std::exception_ptr failure;
    const auto work = [&] {
        try
        {
            detail::TileBuffers t;
            for (size_t i = next++; i < tiles.size(); i = next++)
                detail::buildTile(tg, tiles[i], forEachPoint, t, tile_bricks[i]);
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
    f.brick_of_.assign(size_t(f.bx_) * size_t(f.by_) * size_t(f.bz_), -1);
    for (size_t n = 0; n < tiles.size(); ++n)
        for (auto& [in_tile, values] : tile_bricks[n])
        {
            const Eigen::Vector3i b =
                tiles[n] * kTile + Eigen::Vector3i(in_tile % kTile, in_tile / kTile % kTile, in_tile / (kTile * kTile));
            f.brick_of_[brickIndex(b)] = int(f.bricks_.size());
            f.bricks_.push_back(std::move(values));
        }
    return f;
}

}  // namespace quasiloc::map
