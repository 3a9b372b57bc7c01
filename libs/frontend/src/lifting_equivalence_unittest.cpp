// The fast lifting paths (PixelLifter's projection cache and squared-distance screening, the early exit and
// squared-distance test of fitLine3d, batch lifting of line associations) against the plain versions they
// replaced: the results must be identical, bit for bit.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/frontend/lifting.h>
#include <quasiloc/frontend/plane_hypotheses.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <quasiloc/quasi/synthetic_scene.h>
#include <random>

#include "lifting_detail.h"
#include "test_scenes.h"

using namespace quasiloc;
using namespace quasiloc::frontend;

namespace
{
// ---- The plain versions (as first written): every pixel projected, std::hypot everywhere, every pair counted.

std::optional<LiftedPoint> plainLiftPixel(const quasi::QuasiImage& q, const map::LidarMap& map, const cv::Point2f& px,
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
            const Eigen::Vector3f p = map.point(size_t(idx));
            double X, Y, Z;
            T_cam_world.composePoint(p.x(), p.y(), p.z(), X, Y, Z);
            Eigen::Vector2d u;
            if (!q.camera.project({X, Y, Z}, u)) continue;
            const double d = std::hypot(u.x() - px.x, u.y() - px.y);
            if (d <= accept && (!best || d < best->reprojection_px)) best = LiftedPoint{idx, p, float(d)};
        }
    return best;
}

std::vector<char> plainFitLine3d(const std::vector<Eigen::Vector3f>& pts, float tol, Eigen::Vector3f& c,
                                 Eigen::Vector3f& d)
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

LineSupport plainLineSupport(const quasi::QuasiImage& q, const map::LidarMap& map, const LineSegment& seg,
                             const AssociationOptions& o)
{
    std::vector<int> idx;
    std::vector<Eigen::Vector3f> pts;
    const int S = o.line_support_samples;
    for (int s = 0; s < S; ++s)
    {
        const Eigen::Vector2f p = seg.p0 + (seg.p1 - seg.p0) * ((s + 0.5f) / S);
        const auto l = plainLiftPixel(q, map, {p.x(), p.y()}, o.line_band_px);
        if (!l || std::find(idx.begin(), idx.end(), l->map_index) != idx.end()) continue;
        idx.push_back(l->map_index);
        pts.push_back(l->p_world);
    }
    LineSupport out;
    if (pts.size() < 2) return out;
    const auto inl = plainFitLine3d(pts, float(o.line_support_tolerance_m), out.line_point, out.line_direction);
    for (size_t k = 0; k < pts.size(); ++k)
        if (inl[k]) out.map_indices.push_back(idx[k]), out.points.push_back(pts[k]);
    return out;
}

// ---- Scenes

const map::LidarMap& room()
{
    static const map::LidarMap r = quasi::makeSyntheticRoom(500'000);
    return r;
}

/** EuRoC cam0's radial-tangential model: the distorted projection is what the bench and the tracker lift with. */
core::CameraModel distortedCamera()
{
    core::CameraModel c = core::CameraModel::pinhole(752, 480, 458.654, 457.296, 367.215, 248.375);
    c.model = core::DistortionModel::RadTan;
    c.dist = {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05, 0};
    return c;
}

quasi::QuasiImage render(const mrpt::poses::CPose3D& T_world_cam, const core::CameraModel& camera)
{
    quasi::QuasiRenderer r(room(), quasi::QuasiOptions{});
    quasi::QuasiImage q;
    r.render(T_world_cam, camera, q);
    return q;
}

void expectSameLift(const std::optional<LiftedPoint>& a, const std::optional<LiftedPoint>& b)
{
    ASSERT_EQ(a.has_value(), b.has_value());
    if (!a) return;
    EXPECT_EQ(a->map_index, b->map_index);
    EXPECT_EQ(a->p_world, b->p_world);
    EXPECT_EQ(a->reprojection_px, b->reprojection_px);
}

void expectSameSupport(const LineSupport& a, const LineSupport& b)
{
    EXPECT_EQ(a.map_indices, b.map_indices);
    EXPECT_EQ(a.points, b.points);
    EXPECT_EQ(a.line_point, b.line_point);
    EXPECT_EQ(a.line_direction, b.line_direction);
}

/** Detected segments plus random ones (short, long, partly outside the image). */
std::vector<LineSegment> segmentsOf(const quasi::QuasiImage& q, uint32_t seed)
{
    LineDetector det(LineOptions{});
    std::vector<LineSegment> segs = det.detect(q.gray, q.valid);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> x(-20.f, float(q.width() + 20)), y(-20.f, float(q.height() + 20));
    for (int k = 0; k < 60; ++k)
    {
        const Eigen::Vector2f p0(x(rng), y(rng));
        const Eigen::Vector2f p1 =
            k % 2 ? Eigen::Vector2f(x(rng), y(rng)) : Eigen::Vector2f(p0 + Eigen::Vector2f(25, 7));
        segs.push_back(LineSegment{p0, p1});
    }
    return segs;
}
}  // namespace

TEST(LiftingEquivalence, LiftPixelMatchesThePlainSearch)
{
    for (const auto& camera : {test::testCamera(), distortedCamera()})
    {
        const auto q = render(test::cameraPose(0.3, -0.2, 1.4, 0.4), camera);
        std::mt19937 rng(3);
        std::uniform_real_distribution<float> fx(-3.f, float(q.width() + 3)), fy(-3.f, float(q.height() + 3));
        size_t lifted = 0;
        for (double radius : {0.0, 0.7, 1.5, 2.0, 3.6})
            for (int k = 0; k < 3000; ++k)
            {
                const cv::Point2f px(fx(rng), fy(rng));
                const auto plain = plainLiftPixel(q, room(), px, radius);
                expectSameLift(liftPixel(q, room(), px, radius), plain);
                lifted += plain.has_value();
            }
        EXPECT_GT(lifted, 10000u);  // the comparison is not between two empty results
    }
}

TEST(LiftingEquivalence, OneLifterForManyPixelsMatchesThePlainSearch)
{
    // A small cache shared by far-apart pixels: many slot collisions, which must only cost projections.
    const auto q = render(test::cameraPose(-0.5, 0.4, 1.2, 2.0), distortedCamera());
    detail::PixelLifter lifter(q, room(), 16);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> fx(0.f, float(q.width())), fy(0.f, float(q.height()));
    for (int k = 0; k < 5000; ++k)
    {
        const cv::Point2f px(fx(rng), fy(rng));
        expectSameLift(lifter.lift(px, 1.5), plainLiftPixel(q, room(), px, 1.5));
    }
}

TEST(LiftingEquivalence, LineSupportMatchesThePlainFit)
{
    AssociationOptions o;
    size_t valid = 0, compared = 0;
    for (const auto& camera : {test::testCamera(), distortedCamera()})
        for (const auto& T : {test::cameraPose(0.3, -0.2, 1.4, 0.4), test::cameraPose(-1.0, 0.8, 1.6, -2.2, 0.3)})
        {
            const auto q = render(T, camera);
            for (const auto& seg : segmentsOf(q, uint32_t(compared + 1)))
            {
                const LineSupport plain = plainLineSupport(q, room(), seg, o);
                expectSameSupport(lineSupport(q, room(), seg, o), plain);
                valid += plain.valid(), ++compared;
            }
        }
    EXPECT_GT(valid, compared / 2);
}

TEST(LiftingEquivalence, FitLine3dMatchesThePlainFitAtTheTolerance)
{
    // Points placed at distances from one line that straddle the tolerance by a few ulps: the squared-distance test
    // must hand these to the exact one.
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> t(-2.f, 2.f), jitter(-3e-7f, 3e-7f), noise(-0.2f, 0.2f);
    const float tol = 0.05f;
    for (int trial = 0; trial < 300; ++trial)
    {
        const Eigen::Vector3f p0(t(rng), t(rng), t(rng));
        const Eigen::Vector3f dir = Eigen::Vector3f(t(rng), t(rng), t(rng)).normalized();
        const Eigen::Vector3f normal = dir.unitOrthogonal();
        std::vector<Eigen::Vector3f> pts;
        const int n = 3 + trial % 18;
        for (int k = 0; k < n; ++k)
        {
            const float off = k % 3 == 0 ? tol * (1 + jitter(rng)) : k % 3 == 1 ? 0.2f * jitter(rng) : noise(rng);
            pts.push_back(p0 + t(rng) * dir + off * normal);
        }
        Eigen::Vector3f c_fast, d_fast, c_plain, d_plain;
        const auto fast = detail::fitLine3d(pts, tol, c_fast, d_fast);
        const auto plain = plainFitLine3d(pts, tol, c_plain, d_plain);
        EXPECT_EQ(fast, plain);
        EXPECT_EQ(c_fast, c_plain);
        EXPECT_EQ(d_fast, d_plain);
    }
}

TEST(LiftingEquivalence, BatchLiftingEqualsLiftingEachAssociation)
{
    const auto q = render(test::cameraPose(0.3, -0.2, 1.4, 0.4), distortedCamera());
    LineDetector det(LineOptions{});
    const auto lines = det.detect(q.gray, q.valid);
    ASSERT_GE(lines.size(), 10u);
    AssociationOptions o;
    // Associations sharing candidates, as neighbouring camera lines do.
    std::vector<Association> as;
    for (int k = 0; k + 2 < int(lines.size()); ++k)
        as.push_back(Association{k, {{k, 0.9f, 0.6f}, {k + 1, 0.85f, 0.3f}, {k + 2, 0.8f, 0.1f}}});
    as.push_back(Association{99, {}});
    const auto batch = liftLineAssociations(as, q, room(), lines, o);
    ASSERT_EQ(batch.size(), as.size());
    for (size_t k = 0; k < as.size(); ++k)
    {
        const auto single = liftLineAssociation(as[k], q, room(), lines, o);
        ASSERT_EQ(batch[k].size(), single.size());
        for (size_t c = 0; c < single.size(); ++c)
        {
            EXPECT_EQ(batch[k][c].line_index, single[c].line_index);
            EXPECT_EQ(batch[k][c].probability, single[c].probability);
            expectSameSupport(batch[k][c].support, single[c].support);
            expectSameSupport(single[c].support, plainLineSupport(q, room(), lines[size_t(single[c].line_index)], o));
            ASSERT_EQ(batch[k][c].planes.size(), single[c].planes.size());
            for (size_t p = 0; p < single[c].planes.size(); ++p)
            {
                EXPECT_EQ(batch[k][c].planes[p].side, single[c].planes[p].side);
                EXPECT_EQ(batch[k][c].planes[p].map_indices, single[c].planes[p].map_indices);
                EXPECT_EQ(batch[k][c].planes[p].plane.normal, single[c].planes[p].plane.normal);
                EXPECT_EQ(batch[k][c].planes[p].plane.d, single[c].planes[p].plane.d);
            }
        }
    }
}

TEST(LiftingEquivalence, CandidateOutsideTheLinesIsAnError)
{
    const auto q = render(test::cameraPose(0.3, -0.2, 1.4, 0.4), distortedCamera());
    const std::vector<LineSegment> lines{LineSegment{{100, 100}, {200, 120}}};
    const Association a{0, {{3, 0.9f, 1.f}}};
    EXPECT_THROW(liftLineAssociation(a, q, room(), lines, AssociationOptions{}), core::InputError);
    EXPECT_THROW(liftLineAssociations({a}, q, room(), lines, AssociationOptions{}), core::InputError);
}
