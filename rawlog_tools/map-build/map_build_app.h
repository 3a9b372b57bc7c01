#pragma once
// map-build: LiDAR scans + their trajectory -> a quasiloc LidarMap (libs/map/include/quasiloc/map/map_build.h).
#include <quasiloc/core/program_options.h>
#include <string>

namespace quasiloc::map_build
{
/** --help: the usage, with the [MapBuild] options listed from their declaration. */
std::string usage();
/** The program body for core::runProgram. */
int run(const core::CommandLine& cmd);
}  // namespace quasiloc::map_build
