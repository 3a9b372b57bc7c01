#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/frontend/lifting.h>

namespace quasiloc::frontend
{
std::optional<LiftedPoint> liftPixel(const quasi::QuasiImage& q, const map::LidarMap& map, const cv::Point2f& px,
                                     double search_radius_px)
{
    if (q.provenance.empty()) return std::nullopt;
    const int r = int(std::ceil(search_radius_px));
    const int cx = int(std::lround(px.x)), cy = int(std::lround(px.y));
    const double accept = std::max(search_radius_px, 1.0);
    std::optional<LiftedPoint> best;
    const auto T_cam_world = -q.T_world_cam;
    for (int y = std::max(0, cy - r); y <= std::min(q.provenance.rows - 1, cy + r); ++y)
        for (int x = std::max(0, cx - r); x <= std::min(q.provenance.cols - 1, cx + r); ++x)
        {
            const int idx = q.provenance.at<int32_t>(y, x);
            if (idx < 0) continue;
            core::require(size_t(idx) < map.size(), "quasi-image provenance",
                          "index " + std::to_string(idx) + " is outside the map (" + std::to_string(map.size()) +
                              " points): image and map do not belong together");
            const Eigen::Vector3f p = map.point(size_t(idx));
            double X, Y, Z;
            T_cam_world.composePoint(p.x(), p.y(), p.z(), X, Y, Z);
            Eigen::Vector2d u;
            if (!q.camera.project({X, Y, Z}, u)) continue;
            const double d = std::hypot(u.x() - px.x, u.y() - px.y);
            if (d <= accept && (!best || d < best->reprojection_px))
                best = LiftedPoint{idx, p, float(d)};
        }
    return best;
}

namespace
{
/** Largest subset of `pts` within tol of the line through two of them (all pairs when few, else a fixed
 *  stride over pairs: deterministic). Returns the inlier flags and the line. */
std::vector<char> fitLine3d(const std::vector<Eigen::Vector3f>& pts, float tol, Eigen::Vector3f& c, Eigen::Vector3f& d)
{
    const int n = int(pts.size());
    std::vector<char> best(n, 0), cur(n);
    int best_count = 0;
    const int max_pairs = 60, total = n * (n - 1) / 2, step = std::max(1, total / max_pairs);
    int pair = 0;
    for (int a = 0; a < n; ++a)
        for (int b = a + 1; b < n; ++b, ++pair)
        {
            if (pair % step) continue;
            const Eigen::Vector3f dir = pts[b] - pts[a];
            if (dir.norm() < 1e-4f) continue;
            const Eigen::Vector3f u = dir.normalized();
            int count = 0;
            for (int k = 0; k < n; ++k)
            {
                const Eigen::Vector3f v = pts[k] - pts[a];
                cur[k] = (v - v.dot(u) * u).norm() <= tol;
                count += cur[k];
            }
            if (count > best_count) best_count = count, best = cur;
        }
    // Refine on the inliers: centroid and principal direction.
    Eigen::Vector3f mean = Eigen::Vector3f::Zero();
    for (int k = 0; k < n; ++k)
        if (best[k]) mean += pts[k];
    mean /= float(std::max(1, best_count));
    Eigen::Matrix3f C = Eigen::Matrix3f::Zero();
    for (int k = 0; k < n; ++k)
        if (best[k]) C += (pts[k] - mean) * (pts[k] - mean).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> es(C);
    c = mean;
    d = es.eigenvectors().col(2).normalized();
    return best;
}
}  // namespace

LineSupport lineSupport(const quasi::QuasiImage& q, const map::LidarMap& map, const LineSegment& seg,
                        const AssociationOptions& o)
{
    std::vector<int> idx;
    std::vector<Eigen::Vector3f> pts;
    const int S = o.line_support_samples;
    for (int s = 0; s < S; ++s)
    {
        const Eigen::Vector2f p = seg.p0 + (seg.p1 - seg.p0) * ((s + 0.5f) / S);
        const auto l = liftPixel(q, map, {p.x(), p.y()}, o.line_band_px);
        if (!l || std::find(idx.begin(), idx.end(), l->map_index) != idx.end()) continue;
        idx.push_back(l->map_index);
        pts.push_back(l->p_world);
    }
    LineSupport out;
    if (pts.size() < 2) return out;
    const auto inl = fitLine3d(pts, float(o.line_support_tolerance_m), out.line_point, out.line_direction);
    for (size_t k = 0; k < pts.size(); ++k)
        if (inl[k]) out.map_indices.push_back(idx[k]), out.points.push_back(pts[k]);
    return out;
}
}  // namespace quasiloc::frontend
