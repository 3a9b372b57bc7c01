#pragma once
// Builds the database of virtual views (database.h) from the LiDAR map alone: sample viewpoints
// (view_sampling.h), render a quasi-image at each, extract point features and line segments on it, lift them
// through provenance, drop views that see too little of the map, then train the vocabulary on all views'
// descriptors and index every view. Rendering and extraction run on `threads` workers, each with its own
// renderer and extractor (neither is thread-safe); the result does not depend on the thread count.
//
// In shards (database_shard.h): buildDatabaseShard() renders one tile of the sampled views, finishDatabase() joins
// all shards of a build and trains the vocabulary on the union. buildDatabase() is exactly shard 0/1 + finish.
//
// Options: [BuildDatabase] (DatabaseBuildOptions::declare, database_builder.cpp; the program adds its file keys).
#include <functional>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/frontend/association.h>
#include <quasiloc/frontend/features.h>
#include <quasiloc/frontend/lines.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/quasi/quasi_options.h>
#include <quasiloc/reloc/database.h>
#include <quasiloc/reloc/database_shard.h>
#include <quasiloc/reloc/view_sampling.h>
#include <quasiloc/reloc/vocabulary.h>

namespace quasiloc::reloc
{
struct DatabaseBuildOptions : public core::DeclaredOptions
{
    double min_valid_fraction = 0.3;
    int min_lifted = 30;
    bool store_lines = true;
    int threads = 0;
    /** A quasi-image's pixel-level speckle (one LiDAR point per pixel, each with its own reflectivity noise) changes
     *  with the viewpoint, so corners on it do not repeat between views; blurring (the views and every query,
     *  database.h) leaves the corners of the map's structure. Why 2.5: docs/experiments.md. */
    double image_blur_sigma_px = 2.5;

    void declare(core::OptionTable& t) override;
};

/** Everything the build reads, one struct per INI section. */
struct DatabaseBuildConfig
{
    ViewSamplingOptions sampling;
    quasi::QuasiOptions quasi;
    frontend::FeatureOptions features;
    frontend::LineOptions lines;
    frontend::AssociationOptions association;  ///< lifting radius and line support
    VocabularyOptions vocabulary;
    DatabaseBuildOptions build;
};

struct DatabaseBuildStats
{
    ViewSamplingStats sampling;
    size_t sampled = 0;   ///< views sampled over the whole map
    size_t rendered = 0;  ///< views rendered (a shard's tile; all sampled views in a whole build)
    size_t dropped_valid = 0, dropped_lifted = 0, kept = 0;
    double ms_sampling = 0, ms_views = 0, ms_vocabulary = 0, ms_index = 0;
    double ms_per_view_cpu = 0;  ///< render + extraction + lifting, per view, summed over workers
    int threads = 1;
};

/** Progress: (views processed, views sampled); called from the workers, serialised, about every 1 %. */
using BuildProgress = std::function<void(size_t done, size_t total)>;

/** Samples the views of the whole map and renders shard `shard`'s tile of them (shardViews()). The shard's `map`
 *  identity is left for the caller (it knows the map's file). InputError for an empty map, an unusable camera or
 *  options, no sampled view, or more shards than sampled views. */
DatabaseShard buildDatabaseShard(const map::LidarMap& map, const core::CameraModel& camera,
                                 const DatabaseBuildConfig& config, ShardSelection shard,
                                 DatabaseBuildStats* stats = nullptr, const BuildProgress& progress = {});

/** Joins the shards 0/N .. N-1/N of one build (in that order) into the database: the views in sample order with
 *  ids 0.., the vocabulary trained on all of them, the index. Fills the stats' view counts and vocabulary and index
 *  times. InputError for shards out of order or from different builds (loadShardsForMerge() checks files
 *  fully), a view in two shards, or when no view survives. */
Database finishDatabase(std::vector<DatabaseShard> shards, const VocabularyOptions& vocabulary,
                        DatabaseBuildStats* stats = nullptr);

/** The whole database in one process: buildDatabaseShard(0/1) + finishDatabase(). InputError for an empty map, an
 *  unusable camera or options, or when no view survives. */
Database buildDatabase(const map::LidarMap& map, const core::CameraModel& camera, const DatabaseBuildConfig& config,
                       DatabaseBuildStats* stats = nullptr, const BuildProgress& progress = {});

}  // namespace quasiloc::reloc
