// sim-large-world: a large test world for the large-map features (libs/sim/include/quasiloc/sim/large_world.h):
// the simulated room of a sim-rawlog folder at the centre of a grid of other simulated rooms.
//
//     sim-large-world <config.ini> [--set Section.key=value]... [--print-timing]
//
// Sections: [LargeWorld] (base_map, output, grid_cells, spacing_m, seed, shared_dir), and [World] [Lidar] for the
// other rooms (as sim-rawlog reads them). Outputs, all or nothing: the world map and <output>.ini (the effective
// configuration).
#include <iomanip>
#include <iostream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/sim/large_world.h>

namespace
{
using namespace quasiloc;

const char* kUsage =
    "usage: sim-large-world <config.ini> [--set Section.key=value]... [--print-timing]\n"
    "Builds a large test world: [LargeWorld] base_map (a sim-rawlog lidar_map.map) at the centre of a grid of\n"
    "other simulated rooms ([World], [Lidar]), written to [LargeWorld] output. Example:\n"
    "  sim-large-world share/quasiloc/sim/large_world.ini --set LargeWorld.grid_cells=3";

int run(const core::CommandLine& cmd)
{
    const auto cfg = core::loadConfig(cmd);
    const std::string name = cmd.config_path;
    sim::LargeWorldOptions o;
    sim::WorldOptions world;
    sim::LidarOptions lidar;
    core::loadOptionsChecked(o, cfg, "LargeWorld", name);
    core::loadOptionsChecked(world, cfg, "World", name);
    core::loadOptionsChecked(lidar, cfg, "Lidar", name);
    core::requireInputFiles(name, "LargeWorld", {{"base_map", o.base_map}});
    core::require(!o.output.empty(), name + ": [LargeWorld] output", "is required");

    const map::LidarMap base = map::LidarMap::load(o.base_map);
    std::cout << "base map " << base.summary() << std::endl;
    sim::LargeWorldStats st;
    const map::LidarMap out = sim::buildLargeWorld(base, o, world, lidar, name, &st, [](int done, int total) {
        std::cout << "rooms " << done << "/" << total << std::endl;
    });

    core::StagedOutputs staged;
    out.save(staged.addFile(o.output));
    core::writeEffectiveConfig(staged.addFile(o.output + ".ini"),
                               {{"LargeWorld", &o}, {"World", &world}, {"Lidar", &lidar}},
                               "sim-large-world effective configuration");
    staged.commit();
    std::cout << std::fixed << std::setprecision(2) << "world       " << out.summary() << "\n"
              << "            " << st.rooms << " rooms around the base map (" << st.base_points
              << " points, the world's first), bounding box " << st.area_km2 << " km2\n"
              << "time        " << st.generation_s << " s\n"
              << "outputs     " << o.output << " {,.ini}" << std::endl;
    return 0;
}
}  // namespace

int main(int argc, char** argv) { return core::runProgram(argc, argv, kUsage, run); }
