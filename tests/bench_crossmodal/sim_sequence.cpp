#include "sim_sequence.h"

#include <filesystem>
#include <iostream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/dataset/frame_source.h>
#include <quasiloc/sim/simulation.h>

namespace quasiloc::bench
{
namespace
{
std::string findRawlog(const std::string& dir)
{
    for (const auto& e : std::filesystem::directory_iterator(dir))
        if (e.path().extension() == ".rawlog") return e.path().string();
    throw core::InputError(dir, "no .rawlog file in the simulated folder");
}
}  // namespace

CrossModalSequence loadSimSequence(const std::string& dir, const std::string& world_ini, double start_offset_s,
                                   double duration_s, int max_frames)
{
    namespace fs = std::filesystem;
    if (!fs::exists(dir + "/gt.tum") || !fs::exists(dir + "/lidar_map.map"))
    {
        core::CommandLine cmd;
        cmd.config_path = world_ini;
        cmd.overrides = {{"Simulation.output_dir", dir},
                         {"Simulation.duration_s", std::to_string(duration_s)},
                         {"Simulation.start_offset_s", std::to_string(start_offset_s)},
                         {"Simulation.inspection_png", "false"},
                         {"Simulation.verbose", "false"},
                         // The exact map: the benchmark weighs the two modalities' statistics, not a map's defects.
                         {"Lidar.map_source", "exact"}};
        std::cout << "simulating " << world_ini << " into " << dir << " ..." << std::endl;
        sim::runSimulation(core::loadConfig(cmd), world_ini);
    }
    CrossModalSequence s;
    s.name = fs::path(dir).filename().string();
    s.map = map::LidarMap::load(dir + "/lidar_map.map");
    dataset::FrameSourceOptions fo;
    fo.groundtruth_tum = dir + "/gt.tum";
    fo.calibration_ini = dir + "/calib.ini";
    auto src = dataset::openRawlog(findRawlog(dir), fo);
    s.camera = src->rig().left;
    std::vector<QueryFrame> all;
    dataset::StereoFrame f;
    while (src->next(f))
        if (f.T_world_cam0)
            all.push_back(
                QueryFrame{"sim " + std::to_string(f.index), f.left.clone(), core::toIsometry(*f.T_world_cam0)});
    core::require(!all.empty(), dir, "no frame with ground truth");
    const size_t n = max_frames > 0 ? std::min(all.size(), size_t(max_frames)) : all.size();
    for (size_t i = 0; i < n; ++i) s.frames.push_back(all[i * all.size() / n]);
    return s;
}

}  // namespace quasiloc::bench
