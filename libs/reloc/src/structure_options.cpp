#include <quasiloc/core/error.h>
#include <quasiloc/core/ini_read.h>
#include <quasiloc/reloc/structure_localizer.h>

namespace quasiloc::reloc
{
namespace
{
void declareRetrieval(core::OptionTable& t, StructureLocalizerOptions& o)
{
    using core::Range;
    t.add("downscale", o.downscale, "", Range::between(1, 8),
          "retrieval: views rendered and described at 1/downscale of the camera's resolution");
    t.add("cell_px", o.cell_px, "px", Range::between(4, 256),
          "retrieval: grid cell of the orientation histograms, in full-resolution pixels");
    t.add("max_shift_x_cells", o.max_shift_x_cells, "cells", Range::between(0, 32),
          "retrieval: heading search, the view's grid shifted by up to this many cells left and right");
    t.add("max_shift_y_cells", o.max_shift_y_cells, "cells", Range::between(0, 32),
          "retrieval: pitch search, up and down");
    t.add("min_overlap", o.min_overlap, "", Range::strictlyBetween(0, 1),
          "retrieval: a shift counts when the view's valid cells cover this share of the camera grid");
    t.addEnum("retrieval_score", o.retrieval_score,
              {{"correlation", StructureRetrievalScore::Correlation}, {"peak", StructureRetrievalScore::Peak}},
              "retrieval ranks views by their best shift's correlation, or by how far it stands out of their "
              "correlations at all shifts (peak: views that correlate with anything do not win)");
    t.add("candidates", o.candidates, "", Range::between(1, 200), "retrieved guesses refined by matching and PnP");
    t.add("candidate_separation_m", o.candidate_separation_m, "m", Range::atLeast(0),
          "a retrieved guess this close to a better one ...");
    t.add("candidate_separation_deg", o.candidate_separation_deg, "deg", Range::atLeast(0),
          "... and this close in rotation is skipped");
}

void declareMatching(core::OptionTable& t, StructureLocalizerOptions& o)
{
    using core::Range;
    t.add("keypoints", o.keypoints, "", Range::between(8, 2000),
          "map keypoints per guess (Shi-Tomasi), half on the rank-equalised reflectivity, half on the depth edges");
    t.add("min_keypoint_distance_px", o.min_keypoint_distance_px, "px", Range::atLeast(1),
          "between map keypoints of one channel");
    t.add("min_valid_share", o.min_valid_share, "", Range::between(0, 1),
          "of a map keypoint's descriptor footprint that must be valid");
    t.add("window_base_px", o.window_base_px, "px", Range::atLeast(1),
          "search radius r = base + f (sigma_rad + sigma_m / depth) around the keypoint's pixel at the guess ...");
    t.add("window_max_px", o.window_max_px, "px", Range::atLeast(1), "... at most this");
    t.add("iteration_sigma_m", o.iteration_sigma_m, "m", Range::above(0),
          "the guess's translation uncertainty per iteration (one iteration per value)");
    t.add("iteration_sigma_deg", o.iteration_sigma_deg, "deg", Range::above(0),
          "its rotation uncertainty per iteration (as many values as iteration_sigma_m)");
    t.add("ratio", o.ratio, "", Range::fromUpTo(0, 1),
          "a match is kept when best / second best descriptor distance is below this");
    t.add("consensus_px", o.consensus_px, "px", Range::atLeast(0),
          "before PnP, matches are kept when their displacement from the keypoint's pixel at the guess lies within "
          "this of the displacement most of them share (correct matches move together, wrong ones scatter); 0: off "
          "(with 16 px the simulated room's camera queries localized fewer: docs/crossmodal_matching.md, Part 4)");
    t.add("depth_bands", o.depth_bands, "", Range::between(1, 16), "reflectivity rank-equalised per log-depth band");
    t.add("fill_sigma_px", o.fill_sigma_px, "px", Range::above(0), "quasi-image holes filled before describing");
    t.add("depth_edge_sigma_px", o.depth_edge_sigma_px, "px", Range::above(0),
          "depth-edge channel: window of the local mean of log depth");
    t.add("depth_edge_scale", o.depth_edge_scale, "", Range::above(0), "depth-edge channel: tanh scale (log depth)");
}

void declarePose(core::OptionTable& t, StructureLocalizerOptions& o)
{
    using core::Range;
    t.add("pnp_reproj_px", o.pnp_reproj_px, "px", Range::above(0), "PnP inlier threshold");
    t.add("pnp_max_iterations", o.pnp_max_iterations, "", Range::atLeast(1), "PnP sampling iterations");
    t.add("min_step_inliers", o.min_step_inliers, "", Range::atLeast(4),
          "an iteration's PnP moves the guess only with this many inliers");
    t.add("min_inliers", o.min_inliers, "", Range::atLeast(4), "decision: PnP inliers at the last iteration");
    t.add("min_inlier_ratio", o.min_inlier_ratio, "", Range::between(0, 1),
          "decision: inliers / correspondences at the last iteration");
}
}  // namespace

void StructureLocalizerOptions::declare(core::OptionTable& t)
{
    declareRetrieval(t, *this);
    declareMatching(t, *this);
    declarePose(t, *this);
}

void StructureLocalizerOptions::check(const std::string& input) const
{
    checkRanges(input, "StructureLocalization");
    core::require(!iteration_sigma_m.empty() && iteration_sigma_m.size() == iteration_sigma_deg.size(),
                  input + ": " + core::iniKeyName("StructureLocalization", "iteration_sigma_deg"),
                  "needs as many values as iteration_sigma_m (at least one)");
}

}  // namespace quasiloc::reloc
