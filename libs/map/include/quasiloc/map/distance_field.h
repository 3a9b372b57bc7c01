#pragma once
// DistanceField: the Euclidean distance from any point of a box around the map to the nearest map point, on a
// voxel grid, sampled trilinearly (with the interpolant's gradient).
//
// Why: aligning a stereo point cloud to the map (global localization by geometry, reloc/geometric_localizer.h)
// needs "how far is this point from the map surface, and which way is closer" hundreds of thousands of times;
// a grid lookup is O(1), a k-d tree query is not.
//
// Built as the exact squared distance transform of the occupied voxels' centres (separable 1-D lower envelopes
// of parabolas, Felzenszwalb & Huttenlocher, Theory of Computing 2012), then the square root, truncated at
// max_distance_m. Voxels within one voxel of an occupied one hold the exact distance to the nearby points instead
// (the distance to voxel centres is biased by up to half a voxel, the same way along a whole wall: measured on the
// simulated room, 4 cm voxels put a stereo frame 2.5 cm / 1.1 deg off with centres, 1.0 cm / 0.5 deg exact).
// Values are stored in 16-bit fixed point, steps of max_distance_m / 65535 (7.6 um at 0.5 m, far below the depth noise
// of any stereo point): half the memory of floats, the same in both layouts.
// Memory: a dense grid holds 2 bytes per voxel of the bounding box (a grid larger than max_voxels is an InputError).
// A sparse field stores only the 16^3-voxel bricks within max_distance_m of a map point (every other voxel is at the
// truncation), so its memory grows with the map's surface; a 4-byte brick index covers the bounding box. Its values
// are those of the dense grid, bit for bit: each tile of bricks is transformed with an apron of max_distance_m, and
// a distance up to the truncation only depends on points within it. layout = auto takes the dense grid up to
// dense_max_voxels (a room: faster to build and to query) and the sparse field beyond (a street block, a building).
// A streamed field (distance_field_streamed.h says how) holds only the tiles of bricks near the camera: built from the
// points on demand (or read from a tile cache on disk), evicted least recently used beyond a memory budget. Its values
// are the sparse field's, bit for bit, so its memory is bounded whatever the map's extent (a campus of ground).
#include <Eigen/Core>
#include <quasiloc/map/lidar_map.h>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace quasiloc::map
{
enum class DistanceFieldLayout
{
    Auto,  ///< dense up to dense_max_voxels, sparse beyond (never streamed: a search of the whole map would build it
           ///< all)
    Dense,
    Sparse,
    Streamed  ///< tiles built or read on demand around focus(), least recently used evicted beyond memory_budget_mb
};

namespace detail
{
class StreamedTiles;
}

struct DistanceFieldOptions
{
    double voxel_m = 0.04;
    double margin_m = 1.0;            ///< the grid extends this far beyond the map's bounds
    double max_distance_m = 0.5;      ///< distances are truncated here (and this is the value outside the grid)
    size_t max_voxels = 150'000'000;  ///< a dense grid's cap
    DistanceFieldLayout layout = DistanceFieldLayout::Auto;
    size_t dense_max_voxels = 50'000'000;  ///< layout = auto: dense up to this many voxels (200 MB)
    double memory_budget_mb = 1024;        ///< streamed: tiles held in memory at most (least recently used evicted)
    double focus_radius_m = 12;            ///< streamed: focus() readies the tiles within this distance of the camera
    /// streamed: a folder of tiles on disk (tile_cache.h): read when present, tiles built here are written to it;
    /// empty: none. A cache of another map or other field options is an InputError naming its header.
    std::string tile_cache;

    /** InputError naming `input` for a value that cannot be used. */
    void check(const std::string& input) const;
};

class DistanceField
{
   public:
    /** InputError naming `input` for an empty map or a grid above options.max_voxels. */
    static DistanceField build(const LidarMap& map, const DistanceFieldOptions& options,
                               const std::string& input = "map");

    /** Distance [m] from p (world frame) to the nearest map point; max_distance outside the grid. */
    float distance(const Eigen::Vector3f& p_world) const;
    /** The same, and the gradient of the trilinear interpolant (zero outside the grid). */
    float distance(const Eigen::Vector3f& p_world, Eigen::Vector3f& gradient) const;

    /** Streamed: readies the tiles within focus_radius_m of p_world on a worker thread (the nearest first), so that
     *  the queries of the next frames find them built. A query in a tile not yet ready builds it on its own thread
     *  (never a wrong value). Other layouts: nothing to do. Thread-safe, as are all queries. */
    void focus(const Eigen::Vector3f& p_world) const;
    /** Streamed: blocks until the tiles asked for by the last focus() are ready (benchmarks, tests). */
    void waitForFocus() const;
    /** Streamed: writes every tile of the map to the tile cache (map-build); the number of tiles written. */
    size_t writeAllTiles() const;

    float maxDistance() const { return max_distance_; }
    float voxelSize() const { return voxel_; }
    Eigen::Vector3i dimensions() const { return {nx_, ny_, nz_}; }
    const Eigen::Vector3f& origin() const { return origin_; }  ///< centre of voxel (0, 0, 0)
    /** The stored value at voxel (i, j, k) (no bounds check). */
    float voxel(int i, int j, int k) const
    {
        return streamed_ ? streamedVoxel(i, j, k) : sparse_ ? sparseVoxel(i, j, k) : value(d_[index(i, j, k)]);
    }
    bool sparse() const { return sparse_; }
    bool streamed() const { return streamed_ != nullptr; }
    /** Bytes held: the dense grid, or the bricks and their index, or the resident tiles and the point index. */
    size_t memoryBytes() const;
    size_t allocatedBricks() const;
    /** Streamed: tiles built from points, read from the cache, evicted, and corrupt cache files rebuilt so far. */
    struct StreamStats
    {
        size_t built = 0, read = 0, written = 0, evicted = 0, rebuilt_corrupt = 0, resident = 0, synchronous = 0;
    };
    StreamStats streamStats() const;

   private:
    static constexpr int kBrick = 16, kBrickVoxels = kBrick * kBrick * kBrick;
    static DistanceField buildDense(const LidarMap& map, DistanceField f, const std::string& input,
                                    const DistanceFieldOptions& o);
    static DistanceField buildSparse(const LidarMap& map, DistanceField f);
    static DistanceField buildStreamed(const LidarMap& map, DistanceField f, const DistanceFieldOptions& o,
                                       const std::string& input);
    float streamedVoxel(int i, int j, int k) const;
    float sparseVoxel(int i, int j, int k) const
    {
        const int b =
            brick_of_[(size_t(k / kBrick) * size_t(by_) + size_t(j / kBrick)) * size_t(bx_) + size_t(i / kBrick)];
        if (b < 0) return max_distance_;
        return value(bricks_[size_t(b)][size_t(((k % kBrick) * kBrick + j % kBrick) * kBrick + i % kBrick)]);
    }
    /** Fixed point: a stored step is max_distance / 65535; the top value is the truncation itself. */
    /** Trilinear distance at p_world; the gradient too when `gradient` is set. */
    float sample(const Eigen::Vector3f& p_world, Eigen::Vector3f* gradient) const;
    float value(uint16_t q) const { return q == 65535 ? max_distance_ : float(q) * step_; }
    uint16_t quantize(float d) const { return uint16_t(std::lround(std::min(d, max_distance_) / step_)); }

    size_t index(int i, int j, int k) const { return (size_t(k) * size_t(ny_) + size_t(j)) * size_t(nx_) + size_t(i); }

    Eigen::Vector3f origin_{0, 0, 0};
    float voxel_ = 1, max_distance_ = 0, step_ = 0;
    int nx_ = 0, ny_ = 0, nz_ = 0;
    std::vector<uint16_t> d_;  ///< dense
    bool sparse_ = false;
    int bx_ = 0, by_ = 0, bz_ = 0;  ///< sparse: bricks per axis
    std::vector<int> brick_of_;     ///< sparse: brick (x fastest) -> index into bricks_, -1: all at the truncation
    /** sparse: kBrickVoxels values per brick, x fastest (one allocation each: no doubling of the whole). */
    std::vector<std::vector<uint16_t>> bricks_;
    /** streamed: the tiles (shared by copies of the field; its worker thread ends with the last copy). */
    std::shared_ptr<detail::StreamedTiles> streamed_;
};

}  // namespace quasiloc::map
