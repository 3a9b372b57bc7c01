// Lifting through provenance, line support and plane hypotheses on rendered synthetic maps.
#include <gtest/gtest.h>

#include <quasiloc/core/error.h>
#include <quasiloc/frontend/features.h>
#include <quasiloc/frontend/lifting.h>
#include <quasiloc/frontend/plane_hypotheses.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <quasiloc/quasi/synthetic_scene.h>

#include "test_scenes.h"

using namespace quasiloc;
using namespace quasiloc::frontend;

namespace
{
const map::LidarMap& room()
{
    static const map::LidarMap r = quasi::makeSyntheticRoom(500'000);
    return r;
}

/** A flat checkered wall 3 m in front of a camera at (0, 0, 1.5) looking along world +x. */
const map::LidarMap& wall()
{
    static const map::LidarMap w = [] {
        map::LidarMap m;
        quasi::addPlanarPatch(m, {3, -3, -0.5f}, {0, 6, 0}, {0, 0, 4}, 0.008f, quasi::checkerPattern(0.5f));
        return m;
    }();
    return w;
}

quasi::QuasiImage render(const map::LidarMap& m, const mrpt::poses::CPose3D& T_world_cam)
{
    quasi::QuasiRenderer r(m, quasi::QuasiOptions{});
    quasi::QuasiImage q;
    r.render(T_world_cam, test::testCamera(), q);
    return q;
}

Eigen::Vector2d projectAt(const quasi::QuasiImage& q, const Eigen::Vector3f& p)
{
    double X, Y, Z;
    q.T_world_cam.inverseComposePoint(p.x(), p.y(), p.z(), X, Y, Z);
    Eigen::Vector2d u;
    EXPECT_TRUE(q.camera.project({X, Y, Z}, u));
    return u;
}
}  // namespace

TEST(Lifting, SparsePixelLiftsToItsOwnPoint)
{
    const auto q = render(room(), test::cameraPose(0.3, -0.2, 1.4, 0.4));
    int checked = 0;
    for (int y = 5; y < q.height() - 5; y += 7)
        for (int x = 5; x < q.width() - 5; x += 7)
        {
            if (!q.sparse.at<uchar>(y, x)) continue;
            const auto l = liftPixel(q, room(), cv::Point2f(float(x), float(y)), 0);
            ASSERT_TRUE(l.has_value());
            EXPECT_EQ(l->map_index, q.provenance.at<int32_t>(y, x));
            const Eigen::Vector2d u = projectAt(q, l->p_world);
            EXPECT_LT(std::abs(u.x() - x), 0.5 + 1e-6);
            EXPECT_LT(std::abs(u.y() - y), 0.5 + 1e-6);
            ++checked;
        }
    EXPECT_GT(checked, 500);
}

TEST(Lifting, KeypointsLiftToPointsProjectingOntoThem)
{
    const auto q = render(room(), test::cameraPose(-0.5, 0.4, 1.2, 2.0));
    FeatureOptions fo;
    fo.dense_map = false;
    Features f;
    createFeatureExtractor(fo)->extract(q.gray, q.valid, f);
    ASSERT_GE(f.size(), 100u);
    const double radius = 2.0;
    size_t lifted = 0;
    for (const auto& k : f.keypoints)
    {
        const auto l = liftPixel(q, room(), k.pt, radius);
        if (!l) continue;
        ++lifted;
        const Eigen::Vector2d u = projectAt(q, l->p_world);
        EXPECT_LE(std::hypot(u.x() - k.pt.x, u.y() - k.pt.y), radius + 1e-4);
        EXPECT_NEAR(std::hypot(u.x() - k.pt.x, u.y() - k.pt.y), l->reprojection_px, 1e-3);
    }
    EXPECT_GE(lifted, f.size() * 9 / 10);
}

TEST(Lifting, ProvenanceOfAnotherMapIsAnError)
{
    auto q = render(room(), test::cameraPose(0, 0, 1.5, 0));
    map::LidarMap tiny;
    tiny.addPoint(1, 1, 1, 0.5f);
    bool threw = false;
    for (int y = 200; y < 280 && !threw; ++y)
        for (int x = 300; x < 340 && !threw; ++x)
            if (q.provenance.at<int32_t>(y, x) > 0)
            {
                EXPECT_THROW(liftPixel(q, tiny, cv::Point2f(float(x), float(y)), 0), core::InputError);
                threw = true;
            }
    EXPECT_TRUE(threw);
}

TEST(Lifting, LineSupportLiesOnTheSegmentAndPlanesOnTheWall)
{
    const auto q = render(wall(), test::cameraPose(0, 0, 1.5, 0, 0.0));
    LineOptions lo;
    LineDetector det(lo);
    const auto lines = det.detect(q.gray, q.valid);
    ASSERT_GE(lines.size(), 4u);
    AssociationOptions ao;
    size_t planes = 0;
    for (const auto& seg : lines)
    {
        const LineSupport s = lineSupport(q, wall(), seg, ao);
        ASSERT_TRUE(s.valid());
        for (const auto& p : s.points)
        {
            const Eigen::Vector2d u = projectAt(q, p);
            EXPECT_LE(seg.distanceToLine(u.cast<float>()), ao.line_band_px + 1e-3);
            EXPECT_NEAR(p.x(), 3.0f, 0.02f);  // on the wall
        }
        for (const auto& h : planeHypotheses(q, wall(), seg, ao))
        {
            ++planes;
            EXPECT_GT(std::abs(h.plane.normal.x()), 0.999);
            EXPECT_NEAR(std::abs(h.plane.d), 3.0, 0.01);
            EXPECT_GE(int(h.map_indices.size()), ao.plane_min_points);
        }
    }
    EXPECT_GE(planes, lines.size());  // most segments have a plane on both sides
}

TEST(PlaneFit, DegeneracyChecks)
{
    AssociationOptions o;
    PlaneRejection why;
    std::vector<Eigen::Vector3f> plane, line, thick;
    for (int i = 0; i < 10; ++i)
        for (int j = 0; j < 10; ++j)
        {
            plane.emplace_back(0.05f * i, 0.05f * j, 2.f + 0.001f * float((i * 7 + j * 3) % 5 - 2));
            thick.emplace_back(0.05f * i, 0.05f * j, 2.f + 0.1f * float((i * 7 + j * 3) % 5 - 2));
            line.emplace_back(0.05f * i + 0.01f * j, 0.001f * float(j % 3), 2.f);
        }
    const PlaneFit f = fitPlane(plane, o, why);
    EXPECT_EQ(why, PlaneRejection::None);
    EXPECT_GT(std::abs(f.normal.z()), 0.999);
    EXPECT_NEAR(f.normal.z() * 2.0 + f.d, 0.0, 1e-3);
    fitPlane(line, o, why);
    EXPECT_EQ(why, PlaneRejection::LineLike);
    fitPlane(thick, o, why);
    EXPECT_EQ(why, PlaneRejection::NotFlat);
    fitPlane({plane.begin(), plane.begin() + 5}, o, why);
    EXPECT_EQ(why, PlaneRejection::TooFewPoints);
}
