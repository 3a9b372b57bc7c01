#include <quasiloc/estimation/direct_alignment.h>

namespace quasiloc::estimation
{
void DirectAlignmentOptions::declare(core::OptionTable& t)
{
    using core::Range;
    t.add("pyramid_levels", pyramid_levels, "", Range::between(0, 6),
          "0: full resolution only; level l has 1/2^l of the resolution");
    t.add("camera_blur_sigma_px", camera_blur_sigma_px, "px", Range::between(0, 20),
          "Gaussian blur before the camera's Canny, at every level (level pixels)");
    t.add("canny_high_percentile", canny_high_percentile, "%", Range::strictlyBetween(0, 100),
          "camera Canny high threshold: this percentile of the gradient magnitude");
    t.add("canny_low_ratio", canny_low_ratio, "", Range{0, 1, true, false},
          "camera Canny low threshold = ratio * high");
    t.add("orientation_bins", orientation_bins, "", Range::between(1, 16),
          "edge orientation classes (1: none): an edge pulls only toward camera edges of its class");
    t.add("truncation_px", truncation_px, "px", Range::between(1, 200),
          "distance transform truncation at every level (level pixels): farther points do not pull");
    t.add("huber_px", huber_px, "px", Range::above(0), "Huber threshold on the distance residuals (level pixels)");
    t.add("iterations_per_level", iterations_per_level, "", Range::between(1, 200),
          "Levenberg-Marquardt iterations per pyramid level");
    t.add("max_edge_points", max_edge_points, "", Range::atLeast(20), "map edge points kept (spread over a grid)");
    t.add("model_block_px", model_block_px, "px", Range::between(1, 16),
          "map edges are found on planes reduced by this block size (nearest surface per block)");
    t.add("model_close_px", model_close_px, "", Range::between(0, 8),
          "closing (in blocks) of the inverse depth before depth edges: fills holes");
    t.add("depth_edge_rel", depth_edge_rel, "", Range::above(0),
          "depth edge: a 4-neighbour farther by more than this times the depth");
    t.add("refl_canny_high", refl_canny_high, "", Range{0, 1, true, false},
          "reflectivity edges: Canny high threshold on the reflectivity ([0, 1])");
    t.add("use_reflectivity_edges", use_reflectivity_edges, "map edges from the reflectivity too, not only depth");
    t.add("nmi_bins", nmi_bins, "", Range::between(4, 256), "NMI: joint histogram bins per axis");
    t.add("max_nmi_points", max_nmi_points, "", Range::atLeast(50), "NMI: map points used");
}

}  // namespace quasiloc::estimation
