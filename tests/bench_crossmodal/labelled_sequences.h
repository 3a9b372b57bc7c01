#pragma once
// The cross-modal sequences with a surface class per map point: KITTI classified geometrically
// (geometric_classes.h), the simulator's from the material each map point was sampled on (sim/surface_class.h).
#include <string>
#include <vector>

#include "geometric_classes.h"
#include "kitti_sequence.h"

namespace quasiloc::bench
{
struct LabelledSequence
{
    CrossModalSequence seq;
    std::vector<uint8_t> labels;  ///< sim::SurfaceClass per map point
    std::string column;           ///< how the tables name it, e.g. "KITTI (real)"
};

LabelledSequence loadLabelledKitti(const std::string& dir, int max_frames, const std::string& map_path,
                                   const GeometricClassOptions& options, GeometricClassStats* stats);

/** The simulated sequence of `world_ini` with [World] materials = `materials` in dir_prefix + "_" + materials
 *  (simulated there, with the map's material labels, when that folder has none). */
LabelledSequence loadLabelledSim(const std::string& dir_prefix, const std::string& world_ini,
                                 const std::string& materials, double start_offset_s, double duration_s,
                                 int max_frames);

}  // namespace quasiloc::bench
