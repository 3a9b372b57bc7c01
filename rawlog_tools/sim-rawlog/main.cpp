// sim-rawlog: writes a simulated EuRoC-like sequence (LiDAR map, stereo+IMU rawlog, ground truth, calibration)
// into [Simulation] output_dir. See libs/sim/include/quasiloc/sim/simulation.h for the folder's contents.
#include <iomanip>
#include <iostream>
#include <quasiloc/core/program_options.h>
#include <quasiloc/sim/simulation.h>

namespace
{
const char* kUsage =
    "Usage: sim-rawlog <world.ini> [--set Section.key=value]... [--print-timing]\n"
    "Sections: [Simulation] output_dir (required), sequence, shared_dir, trajectory, duration_s (0 = all),\n"
    "start_offset_s, camera_rate_hz, seed, cam0_yaml, cam1_yaml, ...; [World] world = v1|v2, ...; [Appearance];\n"
    "[Lidar]; [IMU]. Relative paths are relative to the working directory. Example:\n"
    "  sim-rawlog share/quasiloc/sim/V1_01_easy.ini --set Simulation.output_dir=/tmp/s --set Simulation.duration_s=5";

int run(const quasiloc::core::CommandLine& cmd)
{
    const auto cfg = quasiloc::core::loadConfig(cmd);
    const quasiloc::sim::SimulationResult r = quasiloc::sim::runSimulation(cfg, cmd.config_path, cmd.print_timing);
    std::cout << std::fixed << std::setprecision(3) << "points      " << r.map_points
              << (r.beam_map_points ? " (+ " + std::to_string(r.beam_map_points) + " in the 32-beam map)" : "") << "\n"
              << "frames      " << r.frames << " stereo, " << r.imu_samples << " IMU samples\n"
              << "clearance   " << r.world.min_clearance_m << " m (min over the room's trajectories)\n"
              << "generation  world " << r.world_time_s << " s, LiDAR map " << r.map_time_s << " s, total "
              << r.total_time_s << " s\n"
              << "render      " << r.mean_render_ms << " ms per stereo frame (mean), " << r.max_render_ms << " ms max\n"
              << "files:\n";
    for (const auto& f : r.files) std::cout << "  " << f << "\n";
    return 0;
}
}  // namespace

int main(int argc, char** argv) { return quasiloc::core::runProgram(argc, argv, kUsage, run); }
