// quasiloc-track: tracks a stereo + IMU rawlog against a LiDAR map (libs/tracking/tracking_session.h).
//
//     quasiloc-track <config.ini> [--set Section.key=value]... [--print-timing]
//
// Options: docs/options.md ([Tracking] holds the input and output files). Outputs in [Tracking] output_dir, all or
// nothing: trajectory.tum (T_world_cam0), diagnostics.csv (one row per frame), summary.json (the figures printed at
// the end), quasiloc-track.ini (effective configuration), initialization.txt (the attempts of global localization,
// when used) and scene.3Dscene (map, ground truth in green, estimate in red: open with SceneViewer3D).
// Ground truth ([Tracking] groundtruth) is optional, except for [Initialization] init = groundtruth, which starts from
// it: without it the outputs carry no errors, and quasiloc-eval scores trajectory.tum afterwards.
#include <quasiloc/core/program_options.h>

#include "track_app.h"

namespace
{
const char* kUsage =
    "usage: quasiloc-track <config.ini> [--set Section.key=value]... [--print-timing]\n"
    "Tracks a stereo + IMU rawlog against a LiDAR map; writes trajectory.tum, diagnostics.csv, summary.json and the\n"
    "effective configuration into [Tracking] output_dir (docs/quasiloc-track.md, options: docs/options.md).";

int run(const quasiloc::core::CommandLine& cmd) { return quasiloc::app::runTrack(cmd, false); }
}  // namespace

int main(int argc, char** argv) { return quasiloc::core::runProgram(argc, argv, kUsage, run); }
