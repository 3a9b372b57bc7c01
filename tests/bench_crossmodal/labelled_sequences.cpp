#include "labelled_sequences.h"

#include <filesystem>
#include <iostream>
#include <quasiloc/core/program_options.h>
#include <quasiloc/sim/material_labels.h>
#include <quasiloc/sim/simulation.h>
#include <quasiloc/sim/surface_class.h>

#include "sim_sequence.h"

namespace quasiloc::bench
{
LabelledSequence loadLabelledKitti(const std::string& dir, int max_frames, const std::string& map_path,
                                   const GeometricClassOptions& options, GeometricClassStats* stats)
{
    LabelledSequence l;
    l.seq = loadKittiSequence(dir, max_frames, map_path);
    l.labels = classifyGeometrically(l.seq.map, options, stats);
    l.column = "KITTI (real)";
    return l;
}

LabelledSequence loadLabelledSim(const std::string& dir_prefix, const std::string& world_ini,
                                 const std::string& materials, double start_offset_s, double duration_s, int max_frames)
{
    namespace fs = std::filesystem;
    const std::string dir = dir_prefix + "_" + materials;
    if (!fs::exists(fs::path(dir) / sim::kMaterialLabelsFile) || !fs::exists(fs::path(dir) / "gt.tum"))
    {
        core::CommandLine cmd;
        cmd.config_path = world_ini;
        cmd.overrides = {{"Simulation.output_dir", dir},
                         {"Simulation.duration_s", std::to_string(duration_s)},
                         {"Simulation.start_offset_s", std::to_string(start_offset_s)},
                         {"Simulation.inspection_png", "false"},
                         {"Simulation.verbose", "false"},
                         {"Simulation.write_map_materials", "true"},  // labels exist for the exact map only
                         {"Lidar.map_source", "exact"},
                         {"World.materials", materials}};
        std::cout << "simulating " << world_ini << " (materials " << materials << ") into " << dir << " ..."
                  << std::endl;
        sim::runSimulation(core::loadConfig(cmd), world_ini);
    }
    LabelledSequence l;
    l.seq = loadSimSequence(dir, world_ini, start_offset_s, duration_s, max_frames);
    const std::vector<uint16_t> materials_of_points =
        sim::loadMaterialLabels((fs::path(dir) / sim::kMaterialLabelsFile).string(), l.seq.map.size());
    l.labels.resize(materials_of_points.size());
    for (size_t i = 0; i < materials_of_points.size(); ++i)
        l.labels[i] = uint8_t(sim::surfaceClassOf(materials_of_points[i]));
    l.column = "sim " + l.seq.name + " (simulated)";
    return l;
}

}  // namespace quasiloc::bench
