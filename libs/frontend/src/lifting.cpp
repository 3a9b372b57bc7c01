#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/frontend/lifting.h>

#include "lifting_detail.h"

namespace quasiloc::frontend
{
namespace detail
{
namespace
{
// Out of line: the message is only built when it is thrown (it used to be built for every pixel searched).
[[noreturn]] void throwOutsideMap(int idx, size_t map_size)
{
    throw core::InputError("quasi-image provenance", "index " + std::to_string(idx) + " is outside the map (" +
                                                         std::to_string(map_size) +
                                                         " points): image and map do not belong together");
}
}  // namespace

PixelLifter::PixelLifter(const quasi::QuasiImage& q, const map::LidarMap& map, size_t cache_slots)
    : q_(q), map_(map), T_cam_world_(-q.T_world_cam), cache_(cache_slots)
{
    core::require((cache_slots & (cache_slots - 1)) == 0, "PixelLifter", "cache_slots must be 0 or a power of two");
}

bool PixelLifter::project(int idx, double& u, double& v)
{
    auto projectPoint = [&](double& pu, double& pv) {
        const Eigen::Vector3f p = map_.point(size_t(idx));
        double X, Y, Z;
        T_cam_world_.composePoint(p.x(), p.y(), p.z(), X, Y, Z);
        Eigen::Vector2d px(0, 0);
        const bool ok = q_.camera.project({X, Y, Z}, px);
        pu = px.x(), pv = px.y();
        return ok;
    };
    if (cache_.empty()) return projectPoint(u, v);
    Projection& c = cache_[size_t(idx) & (cache_.size() - 1)];
    if (c.idx != idx)
    {
        c.idx = idx;
        c.ok = projectPoint(c.u, c.v);
    }
    u = c.u, v = c.v;
    return c.ok;
}

std::optional<LiftedPoint> PixelLifter::lift(const cv::Point2f& px, double search_radius_px)
{
    const cv::Mat& prov = q_.provenance;
    if (prov.empty()) return std::nullopt;
    const int r = int(std::ceil(search_radius_px));
    const int cx = int(std::lround(px.x)), cy = int(std::lround(px.y));
    const double accept = std::max(search_radius_px, 1.0);
    // Squared distances screen the candidates with a margin far above rounding error; the survivors take the
    // exact tests (std::hypot against accept and against the float distance of the best so far).
    constexpr double kMargin = 1 + 1e-9;
    double screen2 = accept * accept * kMargin;
    std::optional<LiftedPoint> best;
    int previous = -1;
    for (int y = std::max(0, cy - r); y <= std::min(prov.rows - 1, cy + r); ++y)
    {
        const int32_t* row = prov.ptr<int32_t>(y);
        for (int x = std::max(0, cx - r); x <= std::min(prov.cols - 1, cx + r); ++x)
        {
            const int idx = row[x];
            // The same point as the previous pixel has the same distance: it cannot beat (strictly) itself.
            if (idx < 0 || idx == previous) continue;
            previous = idx;
            if (size_t(idx) >= map_.size()) throwOutsideMap(idx, map_.size());
            double u, v;
            if (!project(idx, u, v)) continue;
            const double dx = u - px.x, dy = v - px.y;
            if (dx * dx + dy * dy > screen2) continue;
            const double d = std::hypot(dx, dy);
            if (d <= accept && (!best || d < best->reprojection_px))
            {
                best = LiftedPoint{idx, map_.point(size_t(idx)), float(d)};
                screen2 = double(best->reprojection_px) * double(best->reprojection_px) * kMargin;
            }
        }
    }
    return best;
}
}  // namespace detail

std::optional<LiftedPoint> liftPixel(const quasi::QuasiImage& q, const map::LidarMap& map, const cv::Point2f& px,
                                     double search_radius_px)
{
    return detail::PixelLifter(q, map, 0).lift(px, search_radius_px);
}

std::vector<char> detail::fitLine3d(const std::vector<Eigen::Vector3f>& pts, float tol, Eigen::Vector3f& c,
                                    Eigen::Vector3f& d)
{
    const int n = int(pts.size());
    std::vector<char> best(n, 0), cur(n);
    int best_count = 0;
    const int max_pairs = 60, total = n * (n - 1) / 2, step = std::max(1, total / max_pairs);
    const float tol2_low = tol * tol * (1 - 1e-5f), tol2_high = tol * tol * (1 + 1e-5f);
    int pair = 0;
    for (int a = 0; a < n; ++a)
        for (int b = a + 1; b < n; ++b, ++pair)
        {
            if (pair % step) continue;
            const Eigen::Vector3f dir = pts[b] - pts[a];
            if (dir.norm() < 1e-4f) continue;
            const Eigen::Vector3f u = dir.normalized();
            // Stop as soon as this pair cannot beat the best one any more (only a strictly larger count wins).
            int count = 0, k = 0;
            for (; k < n && count + (n - k) > best_count; ++k)
            {
                const Eigen::Vector3f v = pts[k] - pts[a];
                // norm() <= tol, with the square root only where the squared distance is too close to tol^2 to
                // decide (a sqrt per point and pair was most of the fit's time).
                const float dist2 = (v - v.dot(u) * u).squaredNorm();
                cur[k] = dist2 <= tol2_low || (dist2 <= tol2_high && std::sqrt(dist2) <= tol);
                count += cur[k];
            }
            if (k == n && count > best_count) best_count = count, best = cur;
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

LineSupport detail::lineSupport(PixelLifter& lifter, const LineSegment& seg, const AssociationOptions& o)
{
    std::vector<int> idx;
    std::vector<Eigen::Vector3f> pts;
    const int S = o.line_support_samples;
    idx.reserve(size_t(S)), pts.reserve(size_t(S));
    for (int s = 0; s < S; ++s)
    {
        const Eigen::Vector2f p = seg.p0 + (seg.p1 - seg.p0) * ((s + 0.5f) / S);
        const auto l = lifter.lift({p.x(), p.y()}, o.line_band_px);
        if (!l || std::find(idx.begin(), idx.end(), l->map_index) != idx.end()) continue;
        idx.push_back(l->map_index);
        pts.push_back(l->p_world);
    }
    LineSupport out;
    if (pts.size() < 2) return out;
    const auto inl = detail::fitLine3d(pts, float(o.line_support_tolerance_m), out.line_point, out.line_direction);
    for (size_t k = 0; k < pts.size(); ++k)
        if (inl[k]) out.map_indices.push_back(idx[k]), out.points.push_back(pts[k]);
    return out;
}

LineSupport lineSupport(const quasi::QuasiImage& q, const map::LidarMap& map, const LineSegment& seg,
                        const AssociationOptions& o)
{
    detail::PixelLifter lifter(q, map);
    return detail::lineSupport(lifter, seg, o);
}
}  // namespace quasiloc::frontend
