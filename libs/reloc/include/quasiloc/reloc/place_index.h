#pragma once
// The places of a map and their descriptors (place_descriptor.h), precomputed for the retrieval stage of global
// localization by geometry (place_retrieval.h), built whole or in shards, kept in a file.
//
// Places: the localizer's candidate positions thinned to one per place_spacing_m horizontal cell and height (the
// first in the candidates' grid order), so a place is a candidate position and the localizer finds them again
// from its own candidates. A shard is one tile of the places: their tile order (database_shard.h tileOrder, a
// Hilbert curve over tile_m cells), cut into N nearly equal runs, as the database's shards. A shard file holds its
// places with their index among all places; the merge sorts them by index, and the single-process build is shard
// 0/1 written the same way, so a merged file equals the single-process file byte for byte.
//
// File (little-endian): "QLPLACES" magic, u32 version, the descriptor options, the map's fingerprint (its point
// count and a hash of every 997th point), the shard i/N, the number of places of the whole map, then per place of
// the file: u64 index, 3 x f32 position, cells x f32 profile. Read with checks: a foreign, truncated or corrupt
// file, or another version, is an InputError naming it.
#include <Eigen/Core>
#include <cstdint>
#include <quasiloc/map/distance_field.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/reloc/database_shard.h>
#include <quasiloc/reloc/place_descriptor.h>
#include <string>
#include <vector>

namespace quasiloc::reloc
{
/** A map's point count and a 64-bit FNV-1a hash of the coordinates of every 997th point: cheap on a large map, and
 *  another map or a changed map differs. */
struct MapFingerprint
{
    uint64_t points = 0, hash = 0;
    static MapFingerprint of(const map::LidarMap& map);
    std::string text() const;
    bool operator==(const MapFingerprint& o) const { return points == o.points && hash == o.hash; }
};

/** Indices into `positions` of the places: one per place_spacing_m cell and height (z to the centimetre). */
std::vector<size_t> selectPlaces(const std::vector<Eigen::Vector3d>& positions, double place_spacing_m);

struct PlaceIndex
{
    PlaceDescriptorOptions descriptor;
    MapFingerprint map;
    ShardSelection selection;  ///< 0/1: the whole map
    uint64_t total_places = 0;
    std::vector<uint64_t> ids;               ///< index of each place among all places, ascending
    std::vector<Eigen::Vector3f> positions;  ///< world
    std::vector<float> profiles;             ///< ids.size() x descriptor.cells()

    size_t size() const { return ids.size(); }
    const float* profile(size_t i) const { return profiles.data() + i * descriptor.cells(); }

    /** Writes atomically (temporary file + rename). */
    void save(const std::string& path) const;
    /** InputError naming `path` for a missing, foreign, truncated or corrupt file or another version. */
    static PlaceIndex load(const std::string& path);
};

/** The profiles of shard `s` of `places` (all places' positions, in place order) on the field, on every core. */
PlaceIndex buildPlaceIndex(const map::DistanceField& field, const std::vector<Eigen::Vector3f>& places,
                           const PlaceDescriptorOptions& o, const MapFingerprint& map, ShardSelection s, double tile_m);

/** The whole index from shards 0..N-1 of one build. InputError naming the shard (`names`, as given) that is of
 *  another map, other options or another count of places, a shard given twice or missing, or a place in two. */
PlaceIndex mergePlaceIndexes(const std::vector<PlaceIndex>& shards, const std::vector<std::string>& names);

}  // namespace quasiloc::reloc
