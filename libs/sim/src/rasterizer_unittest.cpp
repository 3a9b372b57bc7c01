#include <gtest/gtest.h>

#include <quasiloc/core/pose.h>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/sim/rasterizer.h>
#include <quasiloc/sim/stereo_renderer.h>

using namespace quasiloc;

namespace
{
const sim::PinholeIntrinsics kK{320, 240, 250.f, 250.f, 159.5f, 119.5f};

/** A fronto-parallel square of half-size h at depth z, centred on (x, y). */
sim::Mesh square(float x, float y, float z, float h, float cell = 0.3f)
{
    sim::Mesh m;
    m.addQuad({x - h, y - h, z}, {2 * h, 0, 0}, {0, 2 * h, 0}, 0, cell);
    return m;
}

/** A material of constant albedo (so intensity centroids measure geometry only). */
sim::Material constantMaterial(uint8_t value)
{
    sim::Material m;
    m.name = "constant";
    m.size_px = 32;
    m.tile_size_m = 1;
    for (int n = 32; n >= 1; n /= 2) m.albedo_mips.push_back(cv::Mat(n, n, CV_8U, cv::Scalar(value)));
    m.reflectivity = cv::Mat(32, 32, CV_32F, cv::Scalar(0.5));
    return m;
}
}  // namespace

TEST(Rasterizer, PlaneAtKnownDepthCoversExpectedPixels)
{
    const sim::Mesh m = square(0, 0, 2.0f, 0.4f);  // projects to +-50 px around the principal point
    sim::VisibilityBuffer buf;
    buf.reset(kK.width, kK.height);
    sim::rasterize(m, kK, Eigen::Isometry3f::Identity(), {}, buf);
    int covered = 0;
    for (int v = 0; v < kK.height; ++v)
        for (int u = 0; u < kK.width; ++u)
        {
            const auto& s = buf.at(u, v);
            const bool inside = std::abs(u - kK.cx) < 49.5f && std::abs(v - kK.cy) < 49.5f;
            const bool outside = std::abs(u - kK.cx) > 50.5f || std::abs(v - kK.cy) > 50.5f;
            if (inside)
            {
                ASSERT_GE(s.tri, 0) << u << "," << v;
                EXPECT_NEAR(s.depth, 2.0f, 1e-4f);
                // Barycentrics reproduce the 3D point on the plane: x = z (u - cx) / fx.
                const sim::Triangle& t = m.triangles[s.tri];
                const Eigen::Vector3f p = (1 - s.b1 - s.b2) * m.vertices[t.v[0]].p + s.b1 * m.vertices[t.v[1]].p +
                                          s.b2 * m.vertices[t.v[2]].p;
                EXPECT_NEAR(p.x(), 2.0f * (u - kK.cx) / kK.fx, 1e-4f);
                EXPECT_NEAR(p.y(), 2.0f * (v - kK.cy) / kK.fy, 1e-4f);
            }
            if (outside)
            {
                ASSERT_EQ(s.tri, -1) << u << "," << v;
            }
            if (s.tri >= 0) ++covered;
        }
    // Edges at cx +- 50 px = 109.5 .. 209.5: exactly 100 x 100 pixel centres inside.
    EXPECT_EQ(covered, 100 * 100);
}

TEST(Rasterizer, NearerSurfaceWinsInAnyDrawOrder)
{
    for (bool near_first : {true, false})
    {
        sim::Mesh m;
        const sim::Mesh near_sq = square(0.1f, 0, 1.5f, 0.3f), far_sq = square(-0.1f, 0, 3.0f, 0.6f);
        m.append(near_first ? near_sq : far_sq);
        m.append(near_first ? far_sq : near_sq);
        const size_t n_first = (near_first ? near_sq : far_sq).triangles.size();
        sim::VisibilityBuffer buf;
        buf.reset(kK.width, kK.height);
        sim::rasterize(m, kK, Eigen::Isometry3f::Identity(), {}, buf);
        const auto& centre = buf.at(static_cast<int>(kK.cx + 10), static_cast<int>(kK.cy));
        EXPECT_NEAR(centre.depth, 1.5f, 1e-4f);
        EXPECT_EQ(centre.tri < static_cast<int>(n_first), near_first);
        const auto& far_only = buf.at(static_cast<int>(kK.cx - 40), static_cast<int>(kK.cy));  // x = -0.48 m at 3 m
        EXPECT_NEAR(far_only.depth, 3.0f, 1e-4f);
    }
}

TEST(Rasterizer, ClipsTrianglesCrossingTheNearPlane)
{
    // A floor 1 m below the camera from z = -1 m (behind) to z = 10 m: the clipped part must have no holes and
    // the depth must follow the plane: y = 1 => z = fy / (v - cy).
    sim::Mesh floor;
    floor.addQuad({-5, 1, -1}, {10, 0, 0}, {0, 0, 11}, 0, 20.f);  // two huge triangles, both cross z = near
    sim::VisibilityBuffer buf;
    buf.reset(kK.width, kK.height);
    sim::rasterize(floor, kK, Eigen::Isometry3f::Identity(), {}, buf);
    for (int v = static_cast<int>(kK.cy) + 30; v < kK.height; ++v)
        for (int u = 40; u < kK.width - 40; ++u)
        {
            const auto& s = buf.at(u, v);
            ASSERT_GE(s.tri, 0) << u << "," << v;
            EXPECT_NEAR(s.depth, kK.fy / (v - kK.cy), 2e-3f * s.depth);
        }
}

TEST(StereoRenderer, RenderedPointMatchesCameraModelProjectionWithDistortion)
{
    const std::string calib = std::string(QUASILOC_SHARED_DIR) + "/data/euroc/calib/";
    const core::StereoRig rig = core::StereoRig::fromEuroc(calib + "cam0_sensor.yaml", calib + "cam1_sensor.yaml");
    sim::AppearanceOptions ao;
    // Targets: small bright squares at known camera-frame points, including the strongly distorted corners.
    const std::vector<Eigen::Vector3f> targets = {{0, 0, 2}, {-1.3f, -0.85f, 2}, {1.2f, 0.8f, 2}, {0.9f, -0.7f, 1.5f}};
    for (const Eigen::Vector3f& p : targets)
    {
        sim::World w;
        w.materials.materials.push_back(constantMaterial(200));
        w.mesh = square(p.x(), p.y(), p.z(), 0.012f);
        w.lights.push_back({Eigen::Vector3f(0, 0, 0), 0.f});
        w.ambient = 1.f;
        w.computeIrradiance();
        sim::StereoRenderer r(w, rig, ao, 1);
        const cv::Mat rad = r.renderRadiance(0, mrpt::poses::CPose3D(), 0);
        double sw = 0, su = 0, sv = 0;
        for (int v = 0; v < rad.rows; ++v)
            for (int u = 0; u < rad.cols; ++u)
            {
                const double val = rad.at<float>(v, u);
                sw += val;
                su += val * u;
                sv += val * v;
            }
        ASSERT_GT(sw, 0) << p.transpose();
        Eigen::Vector2d px;
        ASSERT_TRUE(rig.left.project(p.cast<double>(), px));
        ASSERT_TRUE(rig.left.isInImage(px));
        EXPECT_NEAR(su / sw, px.x(), 0.5) << p.transpose();
        EXPECT_NEAR(sv / sw, px.y(), 0.5) << p.transpose();
    }
}
