#include <algorithm>
#include <cmath>
#include <quasiloc/frontend/association.h>

#include "ini_read.h"

namespace quasiloc::frontend
{
using namespace detail;

void AssociationOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    max_candidates = readInt(cfg, s, "max_candidates", max_candidates);
    temperature = readDouble(cfg, s, "temperature", temperature);
    max_similarity_gap = readDouble(cfg, s, "max_similarity_gap", max_similarity_gap);
    lift_search_radius_px = readDouble(cfg, s, "lift_search_radius_px", lift_search_radius_px);
    line_support_samples = readInt(cfg, s, "line_support_samples", line_support_samples);
    line_band_px = readDouble(cfg, s, "line_band_px", line_band_px);
    line_support_tolerance_m = readDouble(cfg, s, "line_support_tolerance_m", line_support_tolerance_m);
    plane_side_offset_px = readDouble(cfg, s, "plane_side_offset_px", plane_side_offset_px);
    plane_side_width_px = readDouble(cfg, s, "plane_side_width_px", plane_side_width_px);
    plane_min_points = readInt(cfg, s, "plane_min_points", plane_min_points);
    plane_max_rms_m = readDouble(cfg, s, "plane_max_rms_m", plane_max_rms_m);
    plane_min_extent_ratio = readDouble(cfg, s, "plane_min_extent_ratio", plane_min_extent_ratio);
}

void AssociationOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    c.write(s, "max_candidates", max_candidates, 30, 40, "K candidates per feature");
    c.write(s, "temperature", temperature, 30, 40, "softmax temperature on similarities");
    c.write(s, "max_similarity_gap", max_similarity_gap, 30, 40, "keep s >= s_best - gap");
    c.write(s, "lift_search_radius_px", lift_search_radius_px, 30, 40, "lifting search radius");
    c.write(s, "line_support_samples", line_support_samples, 30, 40, "samples along a line for support");
    c.write(s, "line_band_px", line_band_px, 30, 40, "support points project within this of the line");
    c.write(s, "line_support_tolerance_m", line_support_tolerance_m, 30, 40, "support within this of the 3D line");
    c.write(s, "plane_side_offset_px", plane_side_offset_px, 30, 40, "plane band start from the line");
    c.write(s, "plane_side_width_px", plane_side_width_px, 30, 40, "plane band width");
    c.write(s, "plane_min_points", plane_min_points, 30, 40, "minimum plane support");
    c.write(s, "plane_max_rms_m", plane_max_rms_m, 30, 40, "maximum plane fit RMS");
    c.write(s, "plane_min_extent_ratio", plane_min_extent_ratio, 30, 40, "degeneracy: sqrt(l2/l1) minimum");
}

void AssociationOptions::check(const std::string& input) const
{
    const std::string S = "Association";
    requireKey(max_candidates >= 1 && max_candidates <= 64, input, S, "max_candidates", "must be in [1, 64]");
    requireKey(temperature > 0, input, S, "temperature", "must be > 0");
    requireKey(max_similarity_gap >= 0, input, S, "max_similarity_gap", "must be >= 0");
    requireKey(lift_search_radius_px >= 0 && lift_search_radius_px <= 20, input, S, "lift_search_radius_px",
               "must be in [0, 20]");
    requireKey(line_support_samples >= 2, input, S, "line_support_samples", "must be >= 2");
    requireKey(line_band_px >= 0 && line_band_px <= 20, input, S, "line_band_px", "must be in [0, 20]");
    requireKey(line_support_tolerance_m > 0, input, S, "line_support_tolerance_m", "must be > 0");
    requireKey(plane_side_offset_px >= 0, input, S, "plane_side_offset_px", "must be >= 0");
    requireKey(plane_side_width_px >= 1, input, S, "plane_side_width_px", "must be >= 1");
    requireKey(plane_min_points >= 3, input, S, "plane_min_points", "must be >= 3");
    requireKey(plane_max_rms_m > 0, input, S, "plane_max_rms_m", "must be > 0");
    requireKey(plane_min_extent_ratio >= 0 && plane_min_extent_ratio <= 1, input, S, "plane_min_extent_ratio",
               "must be in [0, 1]");
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
