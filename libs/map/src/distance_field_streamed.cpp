// StreamedTiles: the streamed layout of DistanceField (distance_field_streamed.h).
#include "distance_field_streamed.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <iostream>
#include <quasiloc/core/error.h>

namespace quasiloc::map::detail
{
namespace
{
constexpr int kTileVoxels = kTile * kBrick;  ///< voxels per tile side
}  // namespace

StreamedTiles::StreamedTiles(const LidarMap& map, const TileGrid& grid, const DistanceFieldOptions& o,
                             const std::string& input)
    : map_(map),
      grid_(grid),
      tiles_(grid.tiles()),
      budget_bytes_(size_t(o.memory_budget_mb * 1048576.0)),
      radius_(float(o.focus_radius_m))
{
    table_.resize(size_t(tiles_.prod()));
    recent_.fill(table_.size());  // no tile
    if (!o.tile_cache.empty())
        cache_ = std::make_unique<TileCache>(o.tile_cache, grid_, hashMapPoints(map_), map_.size());
    // Without a complete cache the first tiles are built from points: index them now, not in the first frame.
    if (!cache_ || !cache_->complete()) pointIndex();
    (void)input;
    worker_ = std::thread([this] { work(); });
}

StreamedTiles::~StreamedTiles()
{
    {
        std::lock_guard<std::mutex> lock(queue_mutex_);
        stop_ = true;
    }
    queue_cv_.notify_all();
    worker_.join();
}

void StreamedTiles::pointIndex() const
{
    std::call_once(index_once_, [&] {
        const size_t n = map_.size(), count = size_t(tiles_.prod());
        const auto tileIndexOf = [&](size_t p) {
            const Eigen::Vector3i t = (TileGrid::nearestVoxel(grid_.grid(map_.point(p))) / kTileVoxels)
                                          .cwiseMax(0)
                                          .cwiseMin(tiles_ - Eigen::Vector3i::Ones());
            return grid_.tileIndex(t);
        };
        tile_begin_.assign(count + 1, 0);
        for (size_t p = 0; p < n; ++p) ++tile_begin_[tileIndexOf(p) + 1];
        for (size_t t = 0; t < count; ++t) tile_begin_[t + 1] += tile_begin_[t];
        std::vector<uint32_t> next(tile_begin_.begin(), tile_begin_.end() - 1);
        order_.resize(n);
        for (size_t p = 0; p < n; ++p) order_[next[tileIndexOf(p)]++] = uint32_t(p);
        index_bytes_ = (order_.size() + tile_begin_.size()) * sizeof(uint32_t);
    });
}

void StreamedTiles::buildFromPoints(const Eigen::Vector3i& t, TileBricks& bricks) const
{
    pointIndex();
    thread_local TileBuffers buffers;
    const auto forEachPoint = [&](const Eigen::Vector3i& lo, const Eigen::Vector3i& hi, const auto& visit) {
        const Eigen::Vector3i t0 = lo / kTile, t1 = hi / kTile;
        for (int z = t0.z(); z <= t1.z(); ++z)
            for (int y = t0.y(); y <= t1.y(); ++y)
                for (int x = t0.x(); x <= t1.x(); ++x)
                {
                    const size_t i = grid_.tileIndex({x, y, z});
                    for (uint32_t k = tile_begin_[i]; k < tile_begin_[i + 1]; ++k)
                        visit(grid_.grid(map_.point(order_[k])));
                }
    };
    buildTile(grid_, t, forEachPoint, buffers, bricks);
}

std::unique_ptr<StreamedTiles::Tile> StreamedTiles::make(const Eigen::Vector3i& t) const
{
    TileBricks bricks;
    const size_t index = grid_.tileIndex(t);
    bool build = true;
    if (cache_)
    {
        std::string why;
        const TileCache::Read r = cache_->complete() && !cache_->listed(index) ? TileCache::Read::Ok  // empty
                                                                               : cache_->read(t, bricks, why);
        if (r == TileCache::Read::Absent && cache_->complete()) why = "missing, though the cache lists it";
        if (r == TileCache::Read::Ok)
            build = false, ++read_;
        else if (!why.empty())
        {
            std::cerr << "quasiloc: warning: " << cache_->tilePath(t) << ": " << why << "; the tile is rebuilt\n";
            ++corrupt_;
        }
    }
    if (build)
    {
        buildFromPoints(t, bricks);
        ++built_;
        if (cache_ && !bricks.empty()) cache_->write(t, bricks), ++written_;
    }
    auto tile = std::make_unique<Tile>();
    tile->values.resize(bricks.size() * size_t(kBrickVoxels));
    for (size_t b = 0; b < bricks.size(); ++b)
    {
        tile->slot[size_t(bricks[b].first)] = int16_t(b);
        std::memcpy(tile->values.data() + b * size_t(kBrickVoxels), bricks[b].second.data(),
                    size_t(kBrickVoxels) * sizeof(uint16_t));
    }
    return tile;
}

void StreamedTiles::insert(size_t index, std::unique_ptr<Tile> tile) const
{
    std::unique_lock<std::shared_mutex> lock(mutex_);
    if (table_[index]) return;  // another thread made it meanwhile (the same values)
    tile->used = tick_.load(std::memory_order_relaxed);
    resident_bytes_ += tile->bytes();
    table_[index] = std::move(tile);
    resident_.push_back(index);
    recent_[recent_next_++ % recent_.size()] = index;
    if (resident_bytes_ > budget_bytes_) evictLocked();
}

void StreamedTiles::evictLocked() const
{
    // Least recently used first (ties: inserted first). The tiles of the current focus stay, so a budget below what
    // one focus needs is exceeded rather than thrashed, and so do the last 8 inserted: a query's cell spans up to 8
    // tiles, and it retries until it finds them all.
    const uint32_t now = tick_.load(std::memory_order_relaxed);
    const bool focused = now > 1;
    std::stable_sort(resident_.begin(), resident_.end(), [&](size_t a, size_t b) {
        return table_[a]->used.load(std::memory_order_relaxed) < table_[b]->used.load(std::memory_order_relaxed);
    });
    const size_t target = budget_bytes_ / 10 * 9;
    std::vector<size_t> kept;
    for (size_t n = 0; n < resident_.size(); ++n)
    {
        const size_t i = resident_[n];
        const bool in_use = std::find(recent_.begin(), recent_.end(), i) != recent_.end() ||
                            (focused && table_[i]->used.load(std::memory_order_relaxed) == now);
        if (resident_bytes_ <= target || in_use)
        {
            kept.push_back(i);
            continue;
        }
        resident_bytes_ -= table_[i]->bytes();
        table_[i].reset();
        ++evicted_;
    }
    resident_.swap(kept);
}

void StreamedTiles::ensure(const Eigen::Vector3i& t, bool synchronous) const
{
    const size_t index = grid_.tileIndex(t);
    {
        std::shared_lock<std::shared_mutex> lock(mutex_);
        if (table_[index]) return;
    }
    if (synchronous) ++synchronous_;
    insert(index, make(t));
}

const uint16_t* StreamedTiles::brickLocked(int i, int j, int k, uint32_t tick, bool& missing) const
{
    const Tile* tile = table_[grid_.tileIndex(tileOf(i, j, k))].get();
    missing = tile == nullptr;
    if (missing) return nullptr;
    if (tile->used.load(std::memory_order_relaxed) != tick) tile->used.store(tick, std::memory_order_relaxed);
    const int slot =
        tile->slot[size_t((((k / kBrick) % kTile) * kTile + (j / kBrick) % kTile) * kTile + (i / kBrick) % kTile)];
    return slot < 0 ? nullptr : tile->values.data() + size_t(slot) * size_t(kBrickVoxels);
}

void StreamedTiles::cell(int i, int j, int k, uint16_t code[8]) const
{
    const uint16_t truncated = grid_.quantize(grid_.max_distance);
    const uint32_t tick = tick_.load(std::memory_order_relaxed);
    const auto offset = [](int x, int y, int z) {
        return size_t(((z % kBrick) * kBrick + y % kBrick) * kBrick + x % kBrick);
    };
    while (true)
    {
        Eigen::Vector3i absent;
        {
            std::shared_lock<std::shared_mutex> lock(mutex_);
            bool missing = false;
            if (i % kBrick < kBrick - 1 && j % kBrick < kBrick - 1 && k % kBrick < kBrick - 1)
            {  // the cell within one brick (15 cells in 16 along each axis)
                const uint16_t* b = brickLocked(i, j, k, tick, missing);
                if (!missing)
                {
                    const size_t o = offset(i, j, k), dy = kBrick, dz = kBrick * kBrick;
                    for (int c = 0; c < 8; ++c)
                        code[c] = b ? b[o + ((c & 4) ? dz : 0) + ((c & 2) ? dy : 0) + size_t(c & 1)] : truncated;
                    return;
                }
                absent = tileOf(i, j, k);
            }
            else
            {
                int c = 0;
                for (; c < 8 && !missing; ++c)
                {
                    const int x = i + (c & 1), y = j + ((c >> 1) & 1), z = k + ((c >> 2) & 1);
                    const uint16_t* b = brickLocked(x, y, z, tick, missing);
                    if (missing) absent = tileOf(x, y, z);
                    code[c] = b ? b[offset(x, y, z)] : truncated;
                }
                if (!missing) return;
            }
        }
        ensure(absent, true);
    }
}

uint16_t StreamedTiles::voxel(int i, int j, int k) const
{
    while (true)
    {
        {
            std::shared_lock<std::shared_mutex> lock(mutex_);
            bool missing = false;
            const uint16_t* b = brickLocked(i, j, k, tick_.load(std::memory_order_relaxed), missing);
            if (!missing)
                return b ? b[size_t(((k % kBrick) * kBrick + j % kBrick) * kBrick + i % kBrick)]
                         : grid_.quantize(grid_.max_distance);
        }
        ensure(tileOf(i, j, k), true);
    }
}

void StreamedTiles::focus(const Eigen::Vector3f& p_world)
{
    const uint32_t now = tick_.fetch_add(1, std::memory_order_relaxed) + 1;
    const Eigen::Vector3f g = grid_.grid(p_world);
    const float r = radius_ / grid_.voxel;
    const Eigen::Vector3i lo = ((g.array() - r) / float(kTileVoxels)).floor().cast<int>().max(0),
                          hi = ((g.array() + r) / float(kTileVoxels)).floor().cast<int>().min(tiles_.array() - 1);
    std::vector<std::pair<float, Eigen::Vector3i>> missing;
    {
        std::shared_lock<std::shared_mutex> lock(mutex_);
        for (int z = lo.z(); z <= hi.z(); ++z)
            for (int y = lo.y(); y <= hi.y(); ++y)
                for (int x = lo.x(); x <= hi.x(); ++x)
                {
                    const Eigen::Vector3i t(x, y, z);
                    const Eigen::Vector3f box_lo = (t * kTileVoxels).cast<float>(),
                                          box_hi = box_lo + Eigen::Vector3f::Constant(float(kTileVoxels));
                    const float d = (g.cwiseMax(box_lo).cwiseMin(box_hi) - g).norm();
                    if (d > r) continue;
                    if (const Tile* tile = table_[grid_.tileIndex(t)].get())
                        tile->used.store(now, std::memory_order_relaxed);
                    else
                        missing.emplace_back(d, t);
                }
    }
    std::sort(missing.begin(), missing.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    {
        std::lock_guard<std::mutex> lock(queue_mutex_);
        queue_.clear();
        for (const auto& m : missing) queue_.push_back(m.second);
    }
    queue_cv_.notify_one();
}

void StreamedTiles::work()
{
    std::unique_lock<std::mutex> lock(queue_mutex_);
    while (true)
    {
        queue_cv_.wait(lock, [&] { return stop_ || !queue_.empty(); });
        if (stop_) return;
        const Eigen::Vector3i t = queue_.back();
        queue_.pop_back();
        busy_ = true;
        lock.unlock();
        try
        {
            ensure(t, false);
        }
        catch (const std::exception& e)
        {  // a query of this tile builds it again and reports the error on its own thread
            std::cerr << "quasiloc: warning: a distance field tile could not be readied: " << e.what() << "\n";
        }
        lock.lock();
        busy_ = false;
        if (queue_.empty()) idle_cv_.notify_all();
    }
}

void StreamedTiles::waitForFocus()
{
    std::unique_lock<std::mutex> lock(queue_mutex_);
    idle_cv_.wait(lock, [&] { return stop_ || (queue_.empty() && !busy_); });
}

size_t StreamedTiles::writeAll()
{
    core::require(cache_ != nullptr, "DistanceField::writeAllTiles", "the field has no tile_cache folder");
    pointIndex();
    const size_t count = size_t(tiles_.prod());
    std::vector<char> nonempty(count, 0);
    std::atomic<size_t> next{0}, written{0};
    std::mutex failure_mutex;
    std::exception_ptr failure;
    const auto job = [&] {
        try
        {
            TileBricks bricks;
            for (size_t i = next++; i < count; i = next++)
            {
                const Eigen::Vector3i t(int(i % size_t(tiles_.x())), int(i / size_t(tiles_.x()) % size_t(tiles_.y())),
                                        int(i / (size_t(tiles_.x()) * size_t(tiles_.y()))));
                buildFromPoints(t, bricks);
                if (bricks.empty()) continue;
                cache_->write(t, bricks);
                nonempty[i] = 1;
                ++written;
            }
        }
        catch (...)
        {
            std::lock_guard<std::mutex> lock(failure_mutex);
            if (!failure) failure = std::current_exception();
            next = count;
        }
    };
    std::vector<std::thread> pool;
    for (unsigned k = 1; k < std::max(1u, std::thread::hardware_concurrency()); ++k) pool.emplace_back(job);
    job();
    for (auto& th : pool) th.join();
    if (failure) std::rethrow_exception(failure);
    cache_->markComplete(nonempty);
    written_ += written;
    return written;
}

size_t StreamedTiles::memoryBytes() const
{
    std::shared_lock<std::shared_mutex> lock(mutex_);
    return resident_bytes_ + table_.size() * sizeof(table_[0]) + index_bytes_;
}

size_t StreamedTiles::residentBricks() const
{
    std::shared_lock<std::shared_mutex> lock(mutex_);
    size_t n = 0;
    for (const size_t i : resident_) n += table_[i]->values.size() / size_t(kBrickVoxels);
    return n;
}

DistanceField::StreamStats StreamedTiles::stats() const
{
    DistanceField::StreamStats s;
    s.built = built_, s.read = read_, s.written = written_, s.evicted = evicted_, s.rebuilt_corrupt = corrupt_;
    s.synchronous = synchronous_;
    std::shared_lock<std::shared_mutex> lock(mutex_);
    s.resident = resident_.size();
    return s;
}

}  // namespace quasiloc::map::detail
