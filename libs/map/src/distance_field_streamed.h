#pragma once
// StreamedTiles: the streamed layout of DistanceField (distance_field.h). The field's bounding box is cut into tiles
// of kTile^3 bricks (5.12 m at 4 cm); a tile is made when first needed, by reading it from the tile cache on disk
// (tile_cache.h) or by building it from the map points around it (distance_field_tiles.h: the sparse field's values
// to the bit), and held until the memory budget needs room: then the tiles least recently used are evicted, never
// those the current focus or its queries use.
//
// Threads: queries (any thread) take a shared lock for the few loads of a query; a query whose tile is absent builds
// it on its own thread. focus() hands the tiles around the camera, nearest first, to one worker thread. A tile is
// inserted and evicted under the exclusive lock; building and reading happen outside every lock.
// The points are found through a counting sort by tile (4 bytes per point), made when the first tile is built from
// points: a complete tile cache never needs it.
#include <array>
#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <quasiloc/map/distance_field.h>
#include <quasiloc/map/lidar_map.h>
#include <shared_mutex>
#include <thread>
#include <vector>

#include "distance_field_tiles.h"
#include "tile_cache.h"

namespace quasiloc::map::detail
{
class StreamedTiles
{
   public:
    StreamedTiles(const LidarMap& map, const TileGrid& grid, const DistanceFieldOptions& o, const std::string& input);
    ~StreamedTiles();
    StreamedTiles(const StreamedTiles&) = delete;
    StreamedTiles& operator=(const StreamedTiles&) = delete;

    /** The stored codes of the 8 voxels of the cell at (i, j, k) (its corners at +0/+1 on each axis, x fastest). */
    void cell(int i, int j, int k, uint16_t code[8]) const;
    uint16_t voxel(int i, int j, int k) const;

    void focus(const Eigen::Vector3f& p_world);
    void waitForFocus();
    size_t writeAll();

    size_t memoryBytes() const;
    size_t residentBricks() const;
    DistanceField::StreamStats stats() const;

   private:
    struct Tile
    {
        std::vector<int16_t> slot = std::vector<int16_t>(size_t(kTileBricks), -1);  ///< brick in tile -> values
        std::vector<uint16_t> values;                                               ///< kBrickVoxels per kept brick
        size_t bytes() const { return sizeof(Tile) + slot.size() * 2 + values.capacity() * 2; }
        mutable std::atomic<uint32_t> used{0};  ///< the focus tick it was last used in
    };
    /** The brick's values holding voxel (i, j, k); nullptr: all at the truncation. `missing`: the tile is absent. */
    const uint16_t* brickLocked(int i, int j, int k, uint32_t tick, bool& missing) const;
    Eigen::Vector3i tileOf(int i, int j, int k) const
    {
        return {i / (kTile * kBrick), j / (kTile * kBrick), k / (kTile * kBrick)};
    }
    /** Reads or builds tile t (no lock held) and inserts it, unless it is there already. */
    void ensure(const Eigen::Vector3i& t, bool synchronous) const;
    std::unique_ptr<Tile> make(const Eigen::Vector3i& t) const;
    void buildFromPoints(const Eigen::Vector3i& t, TileBricks& bricks) const;
    void insert(size_t index, std::unique_ptr<Tile> tile) const;
    void evictLocked() const;
    void pointIndex() const;
    void work();

    LidarMap map_;  ///< shares the points (LidarMap copies are shallow)
    TileGrid grid_;
    Eigen::Vector3i tiles_;
    size_t budget_bytes_;
    float radius_;
    std::unique_ptr<TileCache> cache_;

    mutable std::shared_mutex mutex_;
    mutable std::vector<std::unique_ptr<Tile>> table_;  ///< by tile index
    mutable std::vector<size_t> resident_;
    mutable size_t resident_bytes_ = 0;
    mutable std::array<size_t, 8> recent_;  ///< the tiles inserted last (never evicted)
    mutable size_t recent_next_ = 0;
    std::atomic<uint32_t> tick_{1};

    mutable std::once_flag index_once_;
    mutable std::vector<uint32_t> order_, tile_begin_;  ///< points by tile: counting sort
    mutable std::atomic<size_t> index_bytes_{0};

    mutable std::mutex queue_mutex_;
    std::condition_variable queue_cv_, idle_cv_;
    std::vector<Eigen::Vector3i> queue_;  ///< the tiles to ready, nearest last
    bool stop_ = false, busy_ = false;
    std::thread worker_;

    mutable std::atomic<size_t> built_{0}, read_{0}, written_{0}, evicted_{0}, corrupt_{0}, synchronous_{0};
};

}  // namespace quasiloc::map::detail
