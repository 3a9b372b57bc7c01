#pragma once
// Simulated query frames for bench_crossmodal: a sim-rawlog folder (simulated here when absent).
#include <string>

#include "kitti_sequence.h"

namespace quasiloc::bench
{
/** The folder `dir` (simulated from `world_ini` for duration_s after start_offset_s when it has no gt.tum or
 *  map), its raw left camera and at most max_frames frames with ground truth, evenly spread. */
CrossModalSequence loadSimSequence(const std::string& dir, const std::string& world_ini, double start_offset_s,
                                   double duration_s, int max_frames);

}  // namespace quasiloc::bench
