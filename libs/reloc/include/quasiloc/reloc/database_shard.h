#pragma once
// A database built in shards: every shard samples the same viewpoints, renders one spatial tile of them
// and writes a shard file (a partial database: its views with their descriptors, no vocabulary); the merge checks
// that the N shards belong together and finishes the database (vocabulary on the union of all views, index). A
// single-process build is shard 0/1 + the same finish (database_builder.h), so a merged database is the
// single-process one byte for byte. Decisions and the file layout: docs/quasiloc-build-db.md.
#include <mrpt/poses/CPose3D.h>

#include <cstdint>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/frontend/features.h>
#include <quasiloc/reloc/database.h>
#include <string>
#include <vector>

namespace quasiloc::reloc
{
struct DatabaseBuildConfig;

/** Shard `index` of `count` ("i/N" on the command line); 0/1 is the whole database. */
struct ShardSelection
{
    int index = 0;
    int count = 1;

    /** "i/N" with 0 <= i < N; InputError naming `input` otherwise. */
    static ShardSelection parse(const std::string& text, const std::string& input);
    std::string text() const { return std::to_string(index) + "/" + std::to_string(count); }
    bool operator==(const ShardSelection& o) const { return index == o.index && count == o.count; }
};

/** The map file a shard was rendered from: its size and a 64-bit FNV-1a hash of its bytes. */
struct MapIdentity
{
    uint64_t file_bytes = 0;
    uint64_t file_hash = 0;

    /** InputError naming `path` when it cannot be read. */
    static MapIdentity ofFile(const std::string& path);
    /** "1234 bytes, FNV-1a 0123456789abcdef" */
    std::string text() const;
    bool operator==(const MapIdentity& o) const { return file_bytes == o.file_bytes && file_hash == o.file_hash; }
};

/** Every option that changes the database, one "[Section] key = value" line each, in a fixed order: the camera,
 *  [BuildDatabase] (but threads and the program's file keys), [ViewSampling], [QuasiImage] (but num_threads),
 *  [Features], [Lines], [Association], [Vocabulary]. Two builds with the same text and the same map give the same
 *  database. */
std::string resultOptionsText(const DatabaseBuildConfig& config, const core::CameraModel& camera);

/** The first option in which two resultOptionsText() differ: "[ViewSampling] grid_spacing_m = 0.4 in <a_name>,
 *  0.5 in <b_name>"; empty when they are equal. */
std::string optionsDifference(const std::string& a, const std::string& a_name, const std::string& b,
                              const std::string& b_name);

/** The sampled views' indices in tile order: views sorted by the position of their horizontal grid cell (cell_m
 *  wide) along a Hilbert curve, then by index, so that a contiguous run of the order covers one connected, compact
 *  region. */
std::vector<size_t> tileOrder(const std::vector<mrpt::poses::CPose3D>& poses, double cell_m);
/** How many of `num_views` tile-ordered views shard `s` renders: the s.index-th of s.count contiguous parts
 *  of nearly equal size (they differ by at most one view). */
size_t shardSize(size_t num_views, ShardSelection s);
/** The indices of the views shard `s` renders (its part of tileOrder()), ascending. */
std::vector<size_t> shardViews(const std::vector<mrpt::poses::CPose3D>& poses, double cell_m, ShardSelection s);

/** A shard of the database: the views one shard rendered and kept, and what the merge checks. */
struct DatabaseShard
{
    ShardSelection selection;
    MapIdentity map;       ///< set by the program from the map file (empty in an in-memory build)
    std::string map_file;  ///< the map's path as the shard's program was given it (informative)
    uint64_t map_points = 0;
    std::string options;         ///< resultOptionsText() of the build
    uint64_t sampled_views = 0;  ///< views sampled over the whole map (every shard samples the same)
    uint64_t rendered = 0;       ///< views this shard rendered (shardSize())
    uint64_t dropped_valid = 0, dropped_lifted = 0;
    double build_seconds = 0;  ///< the shard's wall time (informative; the merged database does not keep it)

    core::CameraModel camera;           ///< what Database keeps of the build, set as the single-process build
    frontend::FeatureOptions features;  ///< sets it
    double image_blur_sigma_px = 0;
    /** The kept views in ascending sample order, id = the view's index among the sampled views; no words, no BoW
     *  vector (they need the merged vocabulary). */
    std::vector<DatabaseView> views;

    /** Writes atomically (temporary file + rename): a process killed while writing leaves no shard file. */
    void save(const std::string& path) const;
    /** InputError naming `path` for a missing, foreign, truncated or corrupt file, or another format version.
     *  `header_only`: stops before the views (cheap: the merge checks every header before it reads any view). */
    static DatabaseShard load(const std::string& path, bool header_only = false);
};

/** "<output>.shard-<i>-of-<N>": where quasiloc-build-db --shard i/N writes shard i of N of the database
 *  `output`. */
std::string shardPath(const std::string& output, ShardSelection s);

/** What every shard of a merge must match: the merge's own inputs. */
struct ShardExpectation
{
    int count = 1;
    MapIdentity map;
    std::string map_file;     ///< for the messages
    std::string options;      ///< resultOptionsText() of the merge's configuration
    std::string config_name;  ///< the merge's configuration file, for the messages
};

/** Loads the `expected.count` shard files of the database `output` (shardPath()) after checking all of them;
 *  InputError naming the file and what is wrong: shards missing (every missing index and its expected file), a
 *  file that is another shard (a copy or a renamed file: its recorded i/N differs from its name), a shard of
 *  another map, a shard built with other options (the first differing option), shards that disagree on the
 *  number of sampled views, a shard with the wrong number of rendered views, a view claimed by two shards. */
std::vector<DatabaseShard> loadShardsForMerge(const std::string& output, const ShardExpectation& expected);

}  // namespace quasiloc::reloc
