#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <quasiloc/map/gmm_surface.h>

#include "test_cloud_files.h"

using namespace quasiloc;
using namespace quasiloc::map;

namespace
{
/** A component with standard deviations (sigma_min, sigma_mid, sigma_max) along the columns of R. */
GmmComponent component(const Eigen::Vector3d& mean, const Eigen::Vector3d& sigmas, const Eigen::Matrix3d& R)
{
    GmmComponent c;
    c.mean = mean;
    c.covariance = R * sigmas.cwiseAbs2().asDiagonal() * R.transpose();
    return c;
}

Eigen::Matrix3d someRotation()
{
    return Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
}
}  // namespace

TEST(GmmSurface, PointsLieOnTheComponentPlaneInsideTheTruncatedEllipse)
{
    const Eigen::Matrix3d R = someRotation();
    const Eigen::Vector3d mean(1.5, -2, 0.8), sigmas(0.002, 0.1, 0.3);
    GmmSurfaceOptions o;
    o.truncation_sigma = 1.5;
    const LidarMap m = sampleGmmSurfaces({component(mean, sigmas, R)}, o);
    ASSERT_GT(m.size(), 100u);
    double max_plane = 0, max_ellipse = 0;
    for (size_t i = 0; i < m.size(); ++i)
    {
        const Eigen::Vector3d d = m.point(i).cast<double>() - mean;
        const Eigen::Vector3d local = R.transpose() * d;  // (normal, mid, max) coordinates
        max_plane = std::max(max_plane, std::abs(local.x()));
        const double eu = local.z() / (1.5 * sigmas.z()), ev = local.y() / (1.5 * sigmas.y());
        max_ellipse = std::max(max_ellipse, eu * eu + ev * ev);
        EXPECT_EQ(m.reflectivity(i), 0.5f);
    }
    EXPECT_LT(max_plane, 1e-5) << "points off the plane spanned by the two largest axes";
    EXPECT_LE(max_ellipse, 1.0 + 1e-4) << "points outside the truncation ellipse";
    EXPECT_GT(max_ellipse, 0.9) << "the ellipse is not filled to its rim";
}

TEST(GmmSurface, PointCountFollowsDensityTimesArea)
{
    const Eigen::Matrix3d R = someRotation();
    for (const double density : {400.0, 2500.0, 10000.0})
    {
        GmmSurfaceOptions o;
        o.density_per_m2 = density;
        GmmSurfaceStats st;
        const LidarMap m = sampleGmmSurfaces({component({0, 0, 0}, {0.001, 0.2, 0.5}, R)}, o, &st);
        const double expected = density * M_PI * (2 * 0.2) * (2 * 0.5);
        EXPECT_NEAR(st.area_m2, M_PI * 0.4 * 1.0, 1e-9);
        // Stratified jitter: only the cells crossed by the rim vary, ~sqrt(perimeter cells).
        EXPECT_NEAR(static_cast<double>(m.size()), expected, 0.02 * expected + 10) << density;
        EXPECT_EQ(st.points, m.size());
    }
    // Many ellipses smaller than one grid cell: the count is still right on average.
    std::vector<GmmComponent> tiny;
    for (int k = 0; k < 4000; ++k) tiny.push_back(component({k * 0.1, 0, 0}, {0.0005, 0.004, 0.006}, R));
    GmmSurfaceOptions o;  // 2 cm spacing, each ellipse 1.6 x 2.4 cm
    const double expected = 4000 * o.density_per_m2 * M_PI * 0.008 * 0.012;
    EXPECT_NEAR(static_cast<double>(sampleGmmSurfaces(tiny, o).size()), expected, 0.05 * expected);
}

TEST(GmmSurface, SkipsAndCountsComponentsThatAreNotFlat)
{
    const Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    std::vector<GmmComponent> comps = {component({0, 0, 0}, {0.001, 0.1, 0.1}, R),  // flat
                                       component({1, 0, 0}, {0.08, 0.1, 0.12}, R),  // blob: 0.8
                                       component({2, 0, 0}, {0.0, 0.0, 0.1}, R)};   // a line: no surface
    comps[0].is_degenerated = true;
    GmmSurfaceOptions o;
    GmmSurfaceStats st;
    const LidarMap m = sampleGmmSurfaces(comps, o, &st);
    EXPECT_EQ(st.components, 3u);
    EXPECT_EQ(st.sampled, 1u);
    EXPECT_EQ(st.skipped_not_flat, 2u);
    EXPECT_EQ(st.degenerated, 1u);
    for (size_t i = 0; i < m.size(); ++i) EXPECT_LT(m.point(i).x(), 0.5f);

    o.max_flatness = 1.0;  // sample every component that has an area
    sampleGmmSurfaces(comps, o, &st);
    EXPECT_EQ(st.sampled, 2u);
    EXPECT_EQ(st.skipped_not_flat, 1u);
}

TEST(GmmSurface, IsDeterministicForASeed)
{
    const std::vector<GmmComponent> comps = {component({0, 0, 0}, {0.001, 0.1, 0.2}, someRotation()),
                                             component({1, 0, 0}, {0.001, 0.05, 0.3}, Eigen::Matrix3d::Identity())};
    GmmSurfaceOptions o;
    const LidarMap a = sampleGmmSurfaces(comps, o), b = sampleGmmSurfaces(comps, o);
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a.point(i), b.point(i));
    // A component's points do not depend on the components before it.
    const LidarMap second = sampleGmmSurfaces({comps[0], comps[1]}, o);
    const LidarMap first_skipped =
        sampleGmmSurfaces({component({0, 0, 0}, {0.1, 0.1, 0.1}, Eigen::Matrix3d::Identity()), comps[1]}, o);
    const size_t n0 = sampleGmmSurfaces({comps[0]}, o).size();
    ASSERT_EQ(second.size() - n0, first_skipped.size());
    for (size_t i = 0; i < first_skipped.size(); ++i) ASSERT_EQ(second.point(n0 + i), first_skipped.point(i));
    o.seed = 2;
    const LidarMap c = sampleGmmSurfaces(comps, o);
    EXPECT_FALSE(c.size() == a.size() && c.point(0) == a.point(0));
}

TEST(GmmSurface, RejectsBadOptionsAndHugeComponents)
{
    const std::vector<GmmComponent> comps = {component({0, 0, 0}, {0.001, 0.1, 0.2}, someRotation())};
    auto with = [&](auto set) {
        GmmSurfaceOptions o;
        set(o);
        return [o, &comps] { sampleGmmSurfaces(comps, o, nullptr, "room.gmm"); };
    };
    test::expectInputError(with([](GmmSurfaceOptions& o) { o.density_per_m2 = 0; }), "room.gmm", "density_per_m2");
    test::expectInputError(with([](GmmSurfaceOptions& o) { o.truncation_sigma = NAN; }), "room.gmm",
                           "truncation_sigma");
    test::expectInputError(with([](GmmSurfaceOptions& o) { o.reflectivity = 1.5; }), "room.gmm", "reflectivity");
    test::expectInputError(with([](GmmSurfaceOptions& o) { o.max_flatness = -1; }), "room.gmm", "max_flatness");
    const std::vector<GmmComponent> huge = {component({0, 0, 0}, {0.001, 100, 100}, Eigen::Matrix3d::Identity())};
    test::expectInputError([&] { sampleGmmSurfaces(huge, GmmSurfaceOptions(), nullptr, "room.gmm"); },
                           "room.gmm (component 0)", "grid cells");
}

TEST(GmmSurface, SamplesTheEurocV1Room)
{
    const std::string path = std::string(QUASILOC_SHARED_DIR) + "/data/euroc/maps/gmm/v1.gmm";
    const GmmImportResult r = importGmm(path, GmmSurfaceOptions(), 0.0);
    EXPECT_EQ(r.stats.components, 3299u);
    EXPECT_EQ(r.stats.degenerated, 3154u);
    EXPECT_EQ(r.stats.skipped_not_flat, 94u);
    EXPECT_NEAR(static_cast<double>(r.stats.points), 2500 * r.stats.area_m2, 0.01 * 2500 * r.stats.area_m2);
    std::printf("[ v1.gmm   ] %zu points, sampled area %.1f m2\n", r.stats.points, r.stats.area_m2);
    EXPECT_GT(r.stats.points, 800000u);
    // Room 1 spans roughly x -4.4..3.7, y -3.5..5.0, z 0..3.4 m (component means, data README).
    const MapBounds b = r.map.bounds();
    EXPECT_NEAR(b.min.x(), -4.4, 0.5);
    EXPECT_NEAR(b.max.x(), 3.7, 0.5);
    EXPECT_NEAR(b.min.y(), -3.5, 0.5);
    EXPECT_NEAR(b.max.y(), 5.0, 0.5);
    EXPECT_NEAR(b.min.z(), 0.0, 0.5);
    EXPECT_NEAR(b.max.z(), 3.4, 0.5);
}
