#include <quasiloc/core/error.h>
#include <quasiloc/estimation/map_refinement.h>

namespace quasiloc::estimation
{
void MapRefinementOptions::declare(core::OptionTable& t)
{
    using core::Range;
    t.add("window_sigmas", window_sigmas, "", Range::above(0),
          "guided window radius in sigmas of the predicted reprojection");
    t.add("min_window_px", min_window_px, "px", Range::atLeast(1), "guided window radius at least");
    t.add("max_window_px", max_window_px, "px", Range::atLeast(1), "guided window radius at most");
    t.add("guided_candidates", guided_candidates, "", Range::between(1, 16), "K candidates kept per camera keypoint");
    t.add("combined_sigma_m", combined_sigma_m, "m", Range::above(0),
          "combined: the direct estimate's assumed uncertainty (its guided window)");
    t.add("combined_sigma_deg", combined_sigma_deg, "deg", Range::above(0), "combined: the same in rotation");
    t.add("min_inliers", min_inliers, "", Range::atLeast(6), "fewer PnP inliers: the feature pose is not trusted");
    t.add("agree_m", agree_m, "m", Range::above(0),
          "combined: the PnP pose must lie this close to the direct pose ...");
    t.add("agree_deg", agree_deg, "deg", Range::above(0), "... and within this rotation");
    t.add("gate_sigmas", gate_sigmas, "", Range::above(0),
          "features/guided: a PnP pose farther than this many sigmas of the prediction is rejected");
    t.add("direct_prior_weight", direct_prior_weight, "", Range::atLeast(0),
          "direct/combined: weight of the prediction prior in the edge cost (0: none)");
    t.add("lift_radius_px", lift_radius_px, "px", Range::between(0, 20),
          "provenance search radius when lifting a Q keypoint");
    t.add("pnp_max_error_px", pnp_max_error_px, "px", Range::above(0), "PnP inlier threshold");
    t.addEnum("quasi_gray", quasi_gray,
              {{"encoding", QuasiGray::Encoding}, {"matched_reflectivity", QuasiGray::MatchedReflectivity}},
              "features of Q on its gray encoding or on its reflectivity matched to the camera's histogram");
}

void MapRefinementOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    DeclaredOptions::loadFromConfigFile(cfg, section);
    direct.loadFromConfigFile(cfg, "DirectAlignment");
}

void MapRefinementOptions::saveToConfigFile(mrpt::config::CConfigFileBase& cfg, const std::string& section) const
{
    DeclaredOptions::saveToConfigFile(cfg, section);
    direct.saveToConfigFile(cfg, "DirectAlignment");
}

void MapRefinementOptions::check(const std::string& input) const
{
    checkRanges(input, "MapRefinement");
    direct.checkRanges(input, "DirectAlignment");
    core::require(min_window_px <= max_window_px, input + ": [MapRefinement] min_window_px/max_window_px",
                  "need min_window_px <= max_window_px");
}

}  // namespace quasiloc::estimation
