// quasiloc-build-places: the place descriptors of a LiDAR map for the retrieval stage of global localization by
// geometry (libs/reloc/include/quasiloc/reloc/place_index.h, docs/place_retrieval.md), whole or in shards.
//
//     quasiloc-build-places <config.ini> [--shard i/N | --merge N] [--set Section.key=value]... [--print-timing]
//
// [BuildPlaces]: map_file, output, tile_m. [GeometricLocalization]: the candidate positions and the place_ keys,
// as the localizer that reads the file will have them (it checks). With --shard i/N only the places of tile run i
// of N go to <output>.shard-i-of-N; --merge N reads the N shard files and writes <output>, the same bytes as a
// build without --shard. Outputs are written under a temporary name and renamed when complete.
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/reloc/geometric_localizer.h>

#include <chrono>
#include <iostream>

namespace
{
using namespace quasiloc;
using Clock = std::chrono::steady_clock;

const char* kUsage =
    "usage: quasiloc-build-places <config.ini> [--shard i/N | --merge N] [--set Section.key=value]... "
    "[--print-timing]\n"
    "Computes the place descriptors of [BuildPlaces] map_file for [GeometricLocalization] places_file.\n"
    "  --shard i/N  only tile run i of N of the places, into <output>.shard-i-of-N\n"
    "  --merge N    join the N shard files into <output> (the same bytes as a build without --shard)";

struct BuildPlacesOptions : public core::DeclaredOptions
{
    std::string map_file, output = "out/places/map.qplaces";
    double tile_m = 32;
    void declare(core::OptionTable& t) override
    {
        t.add("map_file", map_file, "the LiDAR map");
        t.add("output", output, "the place file");
        t.add("tile_m", tile_m, "m", core::Range::above(0),
              "shards: places go to shards by tiles of this size along a Hilbert curve (the result does not depend "
              "on it)");
    }
};

double seconds(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

int run(const core::CommandLine& cmd)
{
    reloc::ShardSelection selection;
    int merge = 0;
    for (size_t i = 0; i < cmd.flags.size(); i += 2)
    {
        const std::string& f = cmd.flags[i];
        core::require(f == "--shard" || f == "--merge", "command line", "unexpected argument '" + f + "'");
        core::require(i + 1 < cmd.flags.size(), "command line (" + f + ")", "needs a value");
        core::require(cmd.flags.size() == 2, "command line", "give one of --shard i/N and --merge N");
        if (f == "--shard")
            selection = reloc::ShardSelection::parse(cmd.flags[i + 1], "command line (--shard)");
        else
        {
            const std::string& v = cmd.flags[i + 1];
            const bool number = !v.empty() && v.size() < 7 && v.find_first_not_of("0123456789") == std::string::npos;
            core::require(number && std::stoi(v) >= 1, "command line (--merge " + v + ")",
                          "the shard count N must be a whole number >= 1");
            merge = std::stoi(v);
        }
    }
    const auto cfg = core::loadConfig(cmd);
    const std::string name = cmd.config_path;
    BuildPlacesOptions bp;
    reloc::GeometricLocalizationOptions go;
    core::loadOptionsChecked(bp, cfg, "BuildPlaces", name);
    core::loadOptionsChecked(go, cfg, "GeometricLocalization", name);
    core::require(!bp.output.empty(), name + ": [BuildPlaces] output", "is required");
    go.check(name);
    const auto t0 = Clock::now();
    if (merge > 0)
    {
        std::vector<reloc::PlaceIndex> shards;
        std::vector<std::string> names;
        for (int i = 0; i < merge; ++i)
        {
            names.push_back(reloc::shardPath(bp.output, {i, merge}));
            shards.push_back(reloc::PlaceIndex::load(names.back()));
        }
        const reloc::PlaceIndex merged = reloc::mergePlaceIndexes(shards, names);
        merged.save(bp.output);
        std::cout << "merged " << merge << " shards: " << merged.size() << " places (" << merged.map.text() << ") in "
                  << seconds(t0) << " s -> " << bp.output << std::endl;
        return 0;
    }
    core::requireInputFiles(name, "BuildPlaces", {{"map_file", bp.map_file}});
    const map::LidarMap map = map::LidarMap::load(bp.map_file);
    std::cout << "map " << bp.map_file << ": " << map.size() << " points, " << seconds(t0) << " s" << std::endl;
    auto t1 = Clock::now();
    const auto field = reloc::GeometricLocalizer::buildField(map, go, bp.map_file);
    const std::vector<Eigen::Vector3f> places =
        reloc::placePositions(reloc::candidatePositions(map, go, bp.map_file), go);
    std::cout << "distance field and " << places.size() << " places in " << seconds(t1) << " s" << std::endl;
    t1 = Clock::now();
    const reloc::PlaceIndex index =
        reloc::buildPlaceIndex(*field, places, go.place, reloc::MapFingerprint::of(map), selection, bp.tile_m);
    const std::string out = selection.count == 1 ? bp.output : reloc::shardPath(bp.output, selection);
    index.save(out);
    std::cout << "shard " << selection.text() << ": " << index.size() << " of " << places.size()
              << " place profiles in " << seconds(t1) << " s, total " << seconds(t0) << " s -> " << out << std::endl;
    return 0;
}
}  // namespace

int main(int argc, char** argv) { return core::runProgram(argc, argv, kUsage, run); }
