#include <quasiloc/core/error.h>
#include <quasiloc/core/ini_read.h>
#include <quasiloc/reloc/localizer.h>

namespace quasiloc::reloc
{
namespace
{
void declareSearch(core::OptionTable& t, LocalizerOptions& o)
{
    using core::Range;
    t.add("retrieval_per_group", o.retrieval_per_group, "", Range::atLeast(1), "views retrieved per group asked for");
    t.add("group_radius_m", o.group_radius_m, "m", Range::atLeast(0),
          "views this close to a group's best view join it");
    t.add("group_heading_deg", o.group_heading_deg, "deg", Range::between(0, 180),
          "... if their viewing directions differ less");
    t.add("views_per_group", o.views_per_group, "", Range::atLeast(1), "views of a group matched with the query");
    t.add("fast_groups", o.fast_groups, "", Range::atLeast(1), "Fast: groups tried");
    t.add("fast_groups_retry", o.fast_groups_retry, "", Range::atLeast(1), "Fast: groups tried when that fails");
    t.add("full_groups", o.full_groups, "", Range::atLeast(1), "Full: groups tried");
    t.add("full_groups_retry", o.full_groups_retry, "", Range::atLeast(1), "Full: groups tried when that fails");
    t.add("pnp_groups", o.pnp_groups, "", Range::atLeast(1), "hypotheses (best re-ranked groups) that get a PnP");
    t.add("min_group_matches", o.min_group_matches, "", Range::atLeast(4),
          "groups with fewer 2D-3D correspondences get no PnP (PnP needs 4 points)");
    t.add("match_level", o.match_level, "", Range::atLeast(0),
          "compare descriptors under the same vocabulary node of this level (0: all)");
    t.add("voting_radius_m", o.voting_radius_m, "m", Range::above(0), "3D candidates closer than this agree");
    t.add("min_votes", o.min_votes, "", Range::atLeast(1), "views of a group that must confirm a correspondence");
}

void declareDecision(core::OptionTable& t, LocalizerOptions& o)
{
    using core::Range;
    t.add("pnp_reproj_px", o.pnp_reproj_px, "px", Range::above(0), "PnP inlier threshold");
    t.addEnum("pnp_method", o.pnp_method, estimation::pnpMethodNames(), "PnP sampler (estimation/absolute_pose.h)");
    t.add("pnp_max_iterations", o.pnp_max_iterations, "", Range::atLeast(1), "PnP sampling iterations");
    t.add("min_inliers", o.min_inliers, "", Range::atLeast(4), "decision: PnP inliers needed");
    t.add("min_inlier_ratio", o.min_inlier_ratio, "", Range::between(0, 1), "decision: share of the correspondences");
    t.add("max_distance_to_views_m", o.max_distance_to_views_m, "m", Range::above(0),
          "decision: the pose lies within this of its group's views");
    t.add("ambiguity_distance_m", o.ambiguity_distance_m, "m", Range::atLeast(0), "a rival pose farther than this ...");
    t.add("ambiguity_ratio", o.ambiguity_ratio, "", core::Range{0, 1, true, false},
          "... with this share of the winner's inliers: ambiguous, not localized");
}
}  // namespace

void LocalizerOptions::declare(core::OptionTable& t)
{
    declareSearch(t, *this);
    declareDecision(t, *this);
}

estimation::AbsolutePoseOptions LocalizerOptions::pnpOptions() const
{
    estimation::AbsolutePoseOptions po;
    po.method = pnp_method;
    po.max_reproj_error_px = pnp_reproj_px;
    po.max_iterations = pnp_max_iterations;
    po.min_inliers = 4;  // the decision (min_inliers, ratio, ambiguity) is made here, not by the solver
    return po;
}

void LocalizerOptions::check(const std::string& input) const
{
    const auto key = [&](const char* k) { return input + ": " + core::iniKeyName("Localization", k); };
    checkRanges(input, "Localization");
    core::require(fast_groups_retry >= fast_groups, key("fast_groups_retry"), "must be >= fast_groups");
    core::require(full_groups_retry >= full_groups, key("full_groups_retry"), "must be >= full_groups");
    matching.check(input);
    core::require(matching.window_px == 0, input + ": " + core::iniKeyName("PointMatching", "window_px"),
                  "must be 0 for global localization (there is no predicted position)");
}

}  // namespace quasiloc::reloc
