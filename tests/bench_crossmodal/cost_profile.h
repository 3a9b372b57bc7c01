#pragma once
// Does a direct term single out the true pose? For every frame: the map model is built from a quasi-image
// rendered at the true pose, and the term at the true pose is compared with the term one step away along each
// of the 12 axis directions (+-x, +-y, +-z by step_m; +-roll, +-pitch, +-yaw by step_deg, camera frame). A
// term that cannot tell the truth from its neighbours cannot pull a perturbed pose back, whatever optimiser
// runs it: this is the quick evidence for a rendering or encoding choice.
#include <quasiloc/estimation/direct_alignment.h>
#include <quasiloc/frontend/frontend.h>
#include <quasiloc/quasi/quasi_renderer.h>

#include "feature_metric_score.h"
#include "kitti_sequence.h"

namespace quasiloc::bench
{
struct CostProfile
{
    int steps = 0;              ///< frames x 12
    int edge_truth_best = 0;    ///< steps where the edge cost is lower at the truth
    int nmi_truth_best = 0;     ///< steps where NMI is higher at the truth
    double mean_edge_rise = 0;  ///< mean of (cost(step) - cost(truth)) / cost(truth)
    double mean_nmi_drop = 0;   ///< mean of NMI(truth) - NMI(step)
    int fm_truth_best = 0;      ///< steps where the feature-metric score is higher at the truth (-1: no dense map)
    double mean_fm_drop = 0;    ///< mean of score(truth) - score(step)
    double mean_valid_fraction = 0, mean_edge_points = 0;
};

/** The 12 neighbours of the profiles: step k in [0, 12) is axis k / 2 (x, y, z by step_m; roll, pitch, yaw by
 *  step_deg, camera frame), sign - for even k, + for odd k; T_world_cam * axisStep(...) is the neighbour. */
Eigen::Isometry3d axisStep(int k, double step_m, double step_deg);

CostProfile profileDirectTerms(const CrossModalSequence& seq, quasi::QuasiRenderer& renderer,
                               const estimation::DirectAlignmentOptions& options, double step_m, double step_deg,
                               frontend::Frontend& frontend, bool matched_reflectivity = false);

}  // namespace quasiloc::bench
