// quasiloc-build-db: renders a database of virtual views from a LiDAR map alone (libs/reloc/database_builder.h)
// for global localization (quasiloc-localize, the tracker's initialisation and relocalization).
//
//     quasiloc-build-db <config.ini> [--shard i/N | --merge N] [--set Section.key=value]... [--print-timing]
//
// [BuildDatabase]: BuildRunOptions::declare (build_options.h: the file keys) and the library's keys
// (database_builder.h). Other sections: [ViewSampling] [QuasiImage] [Features] [Lines] [Association] [Vocabulary].
//
// Outputs, all or nothing: the database, <output>.views.tum (T_world_cam of every kept view, time = view id, for
// SceneViewer3D / plotting) and <output>.ini (the effective configuration). With --shard i/N only the shard file
// <output>.shard-i-of-N; --merge N reads the N shard files and writes the outputs of a whole build, byte for byte
// (docs/quasiloc-build-db.md). Progress goes to the console.
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
#include <string>

#include "build_modes.h"

namespace
{
using namespace quasiloc;

const char* kUsage =
    "usage: quasiloc-build-db <config.ini> [--shard i/N | --merge N] [--set Section.key=value]... [--print-timing]\n"
    "Renders virtual views of a LiDAR map and writes the global-localization database ([BuildDatabase] output).\n"
    "  --shard i/N  render only tile i of N of the sampled views into <output>.shard-i-of-N\n"
    "  --merge N    join the N shard files into the database (the same bytes as a build without --shard)";

struct Mode
{
    bool shard = false, merge = false;
    reloc::ShardSelection selection;
    int merge_count = 0;
};

Mode parseMode(const std::vector<std::string>& flags)
{
    Mode m;
    for (size_t i = 0; i < flags.size(); ++i)
    {
        const std::string& f = flags[i];
        core::require(f == "--shard" || f == "--merge", "command line", "unexpected argument '" + f + "'");
        core::require(!m.shard && !m.merge, "command line (" + f + ")", "give one of --shard i/N and --merge N");
        core::require(i + 1 < flags.size(), "command line (" + f + ")",
                      f == "--shard" ? "needs a shard i/N" : "needs the shard count N");
        const std::string value = flags[++i];
        if (f == "--shard")
        {
            m.shard = true;
            m.selection = reloc::ShardSelection::parse(value, "command line (--shard)");
        }
        else
        {
            m.merge = true;
            const bool number =
                !value.empty() && value.size() < 7 && value.find_first_not_of("0123456789") == std::string::npos;
            core::require(number && std::stoi(value) >= 1, "command line (--merge " + value + ")",
                          "the shard count N must be a whole number >= 1");
            m.merge_count = std::stoi(value);
        }
    }
    return m;
}

int run(const core::CommandLine& cmd)
{
    const Mode mode = parseMode(cmd.flags);
    const app::BuildInputs in = app::loadBuildInputs(cmd);
    if (mode.shard) return app::buildShard(in, mode.selection);
    if (mode.merge) return app::mergeShards(in, mode.merge_count);
    return app::buildWhole(in);
}
}  // namespace

int main(int argc, char** argv) { return core::runProgram(argc, argv, kUsage, run); }
