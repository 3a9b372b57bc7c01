#pragma once
// Association distributions (PAPER_NOTES): a camera feature keeps up to K map-side candidates with scores
// p_ic = softmax_c(s_ic / temperature), sum_c p_ic = 1, the nominal association (the match) first. For points s is
// the descriptor similarity (point_matcher.h), for lines the hybrid-descriptor similarity <f_i, f_j>.
// Candidates far below the nominal one (similarity gap) are not kept: they would only carry numerical noise.
//
// Options: [Association] (AssociationOptions::declare, association.cpp).
#include <quasiloc/core/declared_options.h>
#include <quasiloc/frontend/line_matcher.h>
#include <quasiloc/frontend/point_matcher.h>
#include <string>
#include <vector>

namespace quasiloc::frontend
{
struct AssociationOptions : public core::DeclaredOptions
{
    int max_candidates = 3;
    double temperature = 0.05;
    double max_similarity_gap = 0.15;
    double lift_search_radius_px = 2;
    int line_support_samples = 16;
    double line_band_px = 1.5;
    double line_support_tolerance_m = 0.05;
    double plane_side_offset_px = 3;
    double plane_side_width_px = 10;
    int plane_min_points = 15;
    double plane_max_rms_m = 0.03;
    /** Below it the support is line-like: a plane's rotation about that line is unobservable. */
    double plane_min_extent_ratio = 0.15;

    void declare(core::OptionTable& t) override;
};

struct AssociationCandidate
{
    int index = -1;  ///< feature index on the map side (quasi-image keypoint or line)
    float similarity = 0;
    float probability = 0;  ///< p_ic
};

struct Association
{
    int query = -1;                                ///< camera-side feature index
    std::vector<AssociationCandidate> candidates;  ///< candidates[0] is the nominal association, then by similarity
};

/** candidates[0] is the nominal association and stays first; the others are sorted by similarity, those below
 *  s_nominal - max_similarity_gap and beyond max_candidates dropped; probabilities are the softmax of the
 *  similarities with the temperature and sum to 1. Empty input gives empty output. */
std::vector<AssociationCandidate> associationDistribution(std::vector<AssociationCandidate> candidates,
                                                          const AssociationOptions& options);

/** One association per nominal point match: its train keypoint plus the query's other candidates
 *  (`candidates` from findCandidates with k >= max_candidates). */
std::vector<Association> pointAssociations(const std::vector<PointMatch>& matches,
                                           const std::vector<std::vector<PointCandidate>>& candidates,
                                           const AssociationOptions& options);

/** One association per line match: the matched line plus the gate-allowed lines of highest similarity. */
std::vector<Association> lineAssociations(const LineMatchResult& result, const AssociationOptions& options);

}  // namespace quasiloc::frontend
