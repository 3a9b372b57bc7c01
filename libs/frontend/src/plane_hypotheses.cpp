#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/frontend/plane_hypotheses.h>

#include "lifting_detail.h"

namespace quasiloc::frontend
{
PlaneFit fitPlane(const std::vector<Eigen::Vector3f>& points, const AssociationOptions& o, PlaneRejection& why)
{
    PlaneFit f;
    f.num_points = points.size();
    why = PlaneRejection::TooFewPoints;
    if (int(points.size()) < o.plane_min_points) return f;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& p : points) mean += p.cast<double>();
    mean /= double(points.size());
    Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
    for (const auto& p : points)
    {
        const Eigen::Vector3d v = p.cast<double>() - mean;
        C += v * v.transpose();
    }
    C /= double(points.size());
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);  // ascending eigenvalues
    const Eigen::Vector3d lam = es.eigenvalues().cwiseMax(0.0);
    f.normal = es.eigenvectors().col(0).normalized();
    f.d = -f.normal.dot(mean);
    f.rms_m = std::sqrt(lam(0));
    f.extent_ratio = lam(2) > 0 ? std::sqrt(lam(1) / lam(2)) : 0.0;
    if (f.extent_ratio < o.plane_min_extent_ratio)
        why = PlaneRejection::LineLike;
    else if (f.rms_m > o.plane_max_rms_m)
        why = PlaneRejection::NotFlat;
    else
        why = PlaneRejection::None;
    return f;
}

std::vector<PlaneHypothesis> planeHypotheses(const quasi::QuasiImage& q, const map::LidarMap& map,
                                             const LineSegment& seg, const AssociationOptions& o)
{
    std::vector<PlaneHypothesis> out;
    if (q.provenance.empty() || seg.length() < 1) return out;
    const Eigen::Vector2f d = seg.direction(), left(d.y(), -d.x());
    // A sample every ~4 px along and ~3 px across: neighbouring pixels mostly repeat the same LiDAR point.
    const int along = std::max(2, int(seg.length() / 4));
    const int across = std::max(1, int(o.plane_side_width_px / 3));
    for (int side : {+1, -1})
    {
        PlaneHypothesis h;
        h.side = side;
        h.map_indices.reserve(size_t(along * across));
        for (int a = 0; a < along; ++a)
            for (int k = 0; k < across; ++k)
            {
                const float off = float(o.plane_side_offset_px + (k + 0.5) * o.plane_side_width_px / across);
                const Eigen::Vector2f p = seg.p0 + (seg.p1 - seg.p0) * ((a + 0.5f) / along) + float(side) * off * left;
                const int x = int(std::lround(p.x())), y = int(std::lround(p.y()));
                if (x < 0 || y < 0 || x >= q.provenance.cols || y >= q.provenance.rows) continue;
                const int idx = q.provenance.at<int32_t>(y, x);
                if (idx >= 0 && size_t(idx) < map.size()) h.map_indices.push_back(idx);
            }
        std::sort(h.map_indices.begin(), h.map_indices.end());
        h.map_indices.erase(std::unique(h.map_indices.begin(), h.map_indices.end()), h.map_indices.end());
        std::vector<Eigen::Vector3f> pts;
        pts.reserve(h.map_indices.size());
        for (int idx : h.map_indices) pts.push_back(map.point(size_t(idx)));
        PlaneRejection why;
        h.plane = fitPlane(pts, o, why);
        if (why == PlaneRejection::None) out.push_back(std::move(h));
    }
    return out;
}

namespace
{
const LineSegment& candidateLine(const std::vector<LineSegment>& quasi_lines, int index)
{
    core::require(index >= 0 && size_t(index) < quasi_lines.size(), "line association",
                  "candidate " + std::to_string(index) + " is not one of the " + std::to_string(quasi_lines.size()) +
                      " quasi-image lines");
    return quasi_lines[size_t(index)];
}

LineHypothesis liftCandidate(const AssociationCandidate& c, detail::PixelLifter& lifter, const quasi::QuasiImage& q,
                             const map::LidarMap& map, const std::vector<LineSegment>& quasi_lines,
                             const AssociationOptions& o)
{
    LineHypothesis h;
    h.line_index = c.index;
    h.probability = c.probability;
    const LineSegment& seg = candidateLine(quasi_lines, c.index);
    h.support = detail::lineSupport(lifter, seg, o);
    h.planes = planeHypotheses(q, map, seg, o);
    return h;
}
}  // namespace

std::vector<LineHypothesis> liftLineAssociation(const Association& a, const quasi::QuasiImage& q,
                                                const map::LidarMap& map, const std::vector<LineSegment>& quasi_lines,
                                                const AssociationOptions& o)
{
    detail::PixelLifter lifter(q, map);  // the candidates pass one gate: they are near each other
    std::vector<LineHypothesis> out;
    out.reserve(a.candidates.size());
    for (const auto& c : a.candidates) out.push_back(liftCandidate(c, lifter, q, map, quasi_lines, o));
    return out;
}

std::vector<std::vector<LineHypothesis>> liftLineAssociations(const std::vector<Association>& associations,
                                                              const quasi::QuasiImage& q, const map::LidarMap& map,
                                                              const std::vector<LineSegment>& quasi_lines,
                                                              const AssociationOptions& o)
{
    // A few thousand distinct points lie near all the candidate segments of an image: 4096 slots keep most.
    detail::PixelLifter lifter(q, map, 4096);
    std::vector<std::pair<size_t, size_t>> first;     // (association, candidate) where a line was lifted
    std::vector<int> lifted(quasi_lines.size(), -1);  // quasi line -> its entry in `first`
    std::vector<std::vector<LineHypothesis>> out(associations.size());
    for (size_t k = 0; k < associations.size(); ++k)
        for (const auto& c : associations[k].candidates)
        {
            candidateLine(quasi_lines, c.index);  // InputError for an index outside quasi_lines
            int& slot = lifted[size_t(c.index)];
            if (slot < 0)
            {
                slot = int(first.size());
                first.emplace_back(k, out[k].size());
                out[k].push_back(liftCandidate(c, lifter, q, map, quasi_lines, o));
                continue;
            }
            const auto [ka, kc] = first[size_t(slot)];
            LineHypothesis h = out[ka][kc];  // the same line: the same support and planes
            h.probability = c.probability;
            out[k].push_back(std::move(h));
        }
    return out;
}
}  // namespace quasiloc::frontend
