#pragma once
// TileCache: the tiles of a streamed distance field on disk, one file per tile in a folder, so that a field is read
// instead of built (map-build writes every tile; a tracker writes the tiles it builds).
//
// The folder holds `header.txt` (the map's identity: its point count and a hash of every coordinate, and the field's
// lattice: voxel, truncation, origin, voxels per axis) and a file per tile with a non-empty brick set, `t_X_Y_Z.bin`:
// "QLFT", version, the header's hash, the tile, its bricks (index in the tile, values) and a checksum of all of it.
// A complete cache (every tile written) also has `nonempty.bin`, the tiles that have a file: any other tile holds no
// value below the truncation and is not looked for.
//
// A header that differs from the map and options in use is an InputError naming it (a cache is never used for
// another map). A tile file that cannot be read back exactly (truncated, another header's, a bad checksum) is
// reported as corrupt, with the reason: the streamed field then builds the tile from the points and rewrites it.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "distance_field_tiles.h"

namespace quasiloc::map
{
class LidarMap;

namespace detail
{
/** A 64-bit hash of every point's coordinates and of their count. */
uint64_t hashMapPoints(const LidarMap& map);

class TileCache
{
   public:
    /** Opens the cache in `folder`, or creates it (and its header) when absent. InputError naming the header when it
     *  was written for another map or other options, or naming the folder when it cannot be created. */
    TileCache(const std::string& folder, const TileGrid& grid, uint64_t map_hash, size_t map_points);

    bool complete() const { return complete_; }
    /** Complete caches: whether tile `index` (TileGrid::tileIndex) has a file. */
    bool listed(size_t index) const { return complete_ && nonempty_[index] != 0; }

    enum class Read
    {
        Absent,
        Ok,
        Corrupt
    };
    /** Reads a tile's bricks; Corrupt with `why` set when the file is there but cannot be used. */
    Read read(const Eigen::Vector3i& tile, TileBricks& out, std::string& why) const;
    /** Writes a tile's bricks (a temporary, then renamed: a reader never sees half a file). */
    void write(const Eigen::Vector3i& tile, const TileBricks& bricks) const;
    /** Marks the cache complete: `nonempty` (one byte per tile) says which tiles have a file. */
    void markComplete(const std::vector<char>& nonempty);

    std::string tilePath(const Eigen::Vector3i& tile) const;
    const std::string& headerPath() const { return header_path_; }

   private:
    std::string folder_, header_path_, header_text_;
    uint64_t header_hash_ = 0;
    Eigen::Vector3i tiles_{0, 0, 0};
    bool complete_ = false;
    std::vector<char> nonempty_;
};

}  // namespace detail
}  // namespace quasiloc::map
