#pragma once
// Do the map's geometric lines meet the camera's segments? For every frame, map lines of the quasi-image rendered
// at the true pose (tracking/map_lines.h: normal shading, contrast test, lifting) are associated with the camera
// image's segments within window_px (geometry alone, no descriptor) at the true pose and one step away along each
// of the 12 axis directions, as the cost profile does. Lines that carry the pose associate more at the truth.
#include <quasiloc/frontend/lines.h>
#include <quasiloc/quasi/quasi_renderer.h>

#include "kitti_sequence.h"

namespace quasiloc::bench
{
struct LineProfile
{
    double camera_segments = 0, map_lines = 0;  ///< per frame
    double associated_at_truth = 0;             ///< camera segments with a candidate, per frame
    double associated_one_step = 0;             ///< the same one step away, per frame and step
    int steps = 0, truth_more = 0;              ///< steps where the truth associates more segments
};

LineProfile profileMapLines(const CrossModalSequence& seq, quasi::QuasiRenderer& renderer,
                            const frontend::LineOptions& lines, double window_px, double step_m, double step_deg);
}  // namespace quasiloc::bench
