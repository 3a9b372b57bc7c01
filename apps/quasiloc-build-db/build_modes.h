#pragma once
// quasiloc-build-db's three ways to build (main.cpp picks one from the command line): the whole database in one
// process, one shard of it, or the merge of all shards. Each writes its outputs all or nothing.
#include <quasiloc/core/camera_model.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/frontend/frontend.h>
#include <quasiloc/reloc/database_builder.h>
#include <string>
#include <vector>

#include "build_options.h"

namespace quasiloc::app
{
/** Everything the INI file (and --set) gives, checked; the map is loaded by the modes that render. */
struct BuildInputs
{
    std::string config_name;
    BuildRunOptions run;
    reloc::DatabaseBuildConfig config;
    frontend::FrontendOptions frontend;  ///< the sections the configuration file may hold (written back in .ini)
    core::CameraModel camera;
    bool print_timing = false;

    /** The sections of the effective configuration <output>.ini. */
    std::vector<core::OptionsSection> sections() const;
};

BuildInputs loadBuildInputs(const core::CommandLine& cmd);

/** The database, its views' TUM file and the effective configuration. */
int buildWhole(const BuildInputs& in);
/** The file of shard `shard` (reloc::shardPath()). */
int buildShard(const BuildInputs& in, reloc::ShardSelection shard);
/** The database from its `count` shard files, with the outputs of buildWhole(), identical to them. */
int mergeShards(const BuildInputs& in, int count);

}  // namespace quasiloc::app
