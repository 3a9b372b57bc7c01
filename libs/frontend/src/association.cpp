#include <algorithm>
#include <cmath>
#include <quasiloc/frontend/association.h>

namespace quasiloc::frontend
{
void AssociationOptions::declare(core::OptionTable& t)
{
    using core::Range;
    t.add("max_candidates", max_candidates, "", Range::between(1, 64), "K candidates per feature");
    t.add("temperature", temperature, "", Range::above(0), "softmax temperature on similarities");
    t.add("max_similarity_gap", max_similarity_gap, "", Range::atLeast(0), "keep candidates with s >= s_best - gap");
    t.add("lift_search_radius_px", lift_search_radius_px, "px", Range::between(0, 20),
          "lifting: nearest provenance pixel whose point projects within this");
    t.add("line_support_samples", line_support_samples, "", Range::atLeast(2),
          "lines: samples along the segment for LiDAR support");
    t.add("line_band_px", line_band_px, "px", Range::between(0, 20),
          "lines: support points project within this of the segment");
    t.add("line_support_tolerance_m", line_support_tolerance_m, "m", Range::above(0),
          "lines: support points within this of the 3D line fitted to them");
    t.add("plane_side_offset_px", plane_side_offset_px, "px", Range::atLeast(0),
          "planes: the support band starts this far from the line on each side");
    t.add("plane_side_width_px", plane_side_width_px, "px", Range::atLeast(1), "planes: the support band's width");
    t.add("plane_min_points", plane_min_points, "", Range::atLeast(3), "fewer support points: no plane");
    t.add("plane_max_rms_m", plane_max_rms_m, "m", Range::above(0), "thicker support: not a plane");
    t.add("plane_min_extent_ratio", plane_min_extent_ratio, "", Range::between(0, 1),
          "degeneracy: a support with sqrt(lambda_2 / lambda_1) below this is rejected");
}

std::vector<AssociationCandidate> associationDistribution(std::vector<AssociationCandidate> c,
                                                          const AssociationOptions& o)
{
    if (c.empty()) return c;
    // The nominal candidate (first) stays first; the others follow by similarity.
    std::stable_sort(c.begin() + 1, c.end(), [](const auto& a, const auto& b) { return a.similarity > b.similarity; });
    const float ref = c[0].similarity;
    size_t n = 1;
    while (n < c.size() && int(n) < o.max_candidates && c[n].similarity >= ref - o.max_similarity_gap) ++n;
    c.resize(n);
    float top = ref;
    for (const auto& x : c) top = std::max(top, x.similarity);
    double sum = 0;
    for (auto& x : c) sum += (x.probability = float(std::exp((x.similarity - top) / o.temperature)));
    for (auto& x : c) x.probability = float(x.probability / sum);
    return c;
}

std::vector<Association> pointAssociations(const std::vector<PointMatch>& matches,
                                           const std::vector<std::vector<PointCandidate>>& candidates,
                                           const AssociationOptions& o)
{
    std::vector<Association> out;
    out.reserve(matches.size());
    for (const auto& m : matches)
    {
        std::vector<AssociationCandidate> c{{m.train, m.similarity, 0.f}};
        for (const auto& pc : candidates[m.query])
            if (pc.index != m.train) c.push_back({pc.index, pc.similarity, 0.f});
        out.push_back(Association{m.query, associationDistribution(std::move(c), o)});
    }
    return out;
}

std::vector<Association> lineAssociations(const LineMatchResult& r, const AssociationOptions& o)
{
    std::vector<Association> out;
    for (const auto& m : r.matches)
    {
        std::vector<AssociationCandidate> c{{m.train, m.similarity, 0.f}};
        for (int j = 0; j < int(r.similarity.cols()); ++j)
            if (j != m.train && r.allowed(m.query, j)) c.push_back({j, r.similarity(m.query, j), 0.f});
        out.push_back(Association{m.query, associationDistribution(std::move(c), o)});
    }
    return out;
}
}  // namespace quasiloc::frontend
