// Tests of QuasiRenderer: provenance (a), occlusion (b), depth step (c), frame-chain invariance (d), and the
// z-buffer against a brute-force double-precision reference.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/core/error.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <quasiloc/quasi/synthetic_scene.h>

using namespace quasiloc;
using mrpt::poses::CPose3D;

namespace
{
core::CameraModel eurocCam0()
{
    return core::CameraModel::fromEurocYaml(std::string(QUASILOC_SHARED_DIR) + "/data/euroc/calib/cam0_sensor.yaml");
}

/** Camera (z forward, x right, y down) at `position`, heading `yaw` about world z, pitched down a little. */
CPose3D cameraPose(double x, double y, double z, double yaw, double pitch)
{
    const CPose3D T_body_cam(0, 0, 0, -M_PI / 2, 0, -M_PI / 2);
    return CPose3D(x, y, z, yaw, pitch, 0.0) + T_body_cam;
}

Eigen::Vector3d toCam(const CPose3D& T_world_cam, const Eigen::Vector3f& p_world)
{
    double x, y, z;
    T_world_cam.inverseComposePoint(p_world.x(), p_world.y(), p_world.z(), x, y, z);
    return {x, y, z};
}

/** Appends a camera-frame patch (x0..x1, y0..y1 at depth z) to the map, in world coordinates. */
size_t addCameraPlane(map::LidarMap& m, const CPose3D& T_world_cam, double x0, double x1, double y0, double y1,
                      double z, float spacing, const quasi::ReflectivityPattern& pattern, uint32_t seed)
{
    map::LidarMap local;
    quasi::addPlanarPatch(local, {float(x0), float(y0), float(z)}, {float(x1 - x0), 0, 0}, {0, float(y1 - y0), 0},
                          spacing, pattern, 0.3f, seed);
    for (size_t i = 0; i < local.size(); ++i)
    {
        double X, Y, Z;
        T_world_cam.composePoint(local.xs()[i], local.ys()[i], local.zs()[i], X, Y, Z);
        m.addPoint(float(X), float(Y), float(Z), local.reflectivity(i));
    }
    return local.size();
}

const map::LidarMap& smallRoom()
{
    static const map::LidarMap room = quasi::makeSyntheticRoom(400'000);
    return room;
}

bool sameMat(const cv::Mat& a, const cv::Mat& b)
{
    if (a.size() != b.size() || a.type() != b.type()) return false;
    for (int y = 0; y < a.rows; ++y)
        if (std::memcmp(a.ptr(y), b.ptr(y), a.cols * a.elemSize()) != 0) return false;
    return true;
}

bool sameQuasi(const quasi::QuasiImage& a, const quasi::QuasiImage& b)
{
    return sameMat(a.bgr, b.bgr) && sameMat(a.gray, b.gray) && sameMat(a.depth, b.depth) &&
           sameMat(a.reflectivity, b.reflectivity) && sameMat(a.valid, b.valid) && sameMat(a.sparse, b.sparse) &&
           sameMat(a.provenance, b.provenance);
}
}  // namespace

// (a) Every valid pixel's provenance point projects into the pixel (sparse) or within the completion radius
// (completed); sparse pixels carry the point's exact depth and reflectivity.
TEST(QuasiRenderer, ProvenanceProjectsOntoItsPixel)
{
    const map::LidarMap& map = smallRoom();
    const core::CameraModel cam = eurocCam0();
    quasi::QuasiOptions o;
    quasi::QuasiRenderer renderer(map, o);
    quasi::QuasiImage q;
    for (const CPose3D& T : {cameraPose(-0.5, 0.3, 1.3, 0.6, 0.2), cameraPose(1.0, -1.0, 1.6, 2.5, 0.35)})
    {
        renderer.render(T, cam, q);
        size_t n_sparse = 0, n_completed = 0;
        double worst_sparse = 0, worst_completed = 0;
        for (int y = 0; y < q.height(); ++y)
            for (int x = 0; x < q.width(); ++x)
            {
                const int32_t idx = q.provenance.at<int32_t>(y, x);
                ASSERT_EQ(idx >= 0, q.valid.at<uint8_t>(y, x) != 0);
                if (idx < 0) continue;
                ASSERT_LT(size_t(idx), map.size());
                const Eigen::Vector3d p = toCam(T, map.point(idx));
                Eigen::Vector2d px;
                ASSERT_TRUE(cam.project(p, px));
                const double err = std::max(std::abs(px.x() - x), std::abs(px.y() - y));
                if (q.sparse.at<uint8_t>(y, x))
                {
                    ++n_sparse;
                    worst_sparse = std::max(worst_sparse, err);
                    EXPECT_NEAR(q.depth.at<float>(y, x), p.z(), 1e-5 * p.z());
                    EXPECT_EQ(q.reflectivity.at<float>(y, x), map.reflectivity(idx));
                }
                else
                {
                    ++n_completed;
                    worst_completed = std::max(worst_completed, err);
                }
            }
        // Float projection: a point on a pixel border may land on either side by ~1e-4 px.
        EXPECT_LE(worst_sparse, 0.5 + 1e-3);
        EXPECT_LE(worst_completed, o.completion_radius_px + 0.5 + 1e-3);
        EXPECT_GT(n_sparse, 50'000u);  // the checks above covered many pixels of both kinds
        EXPECT_GT(n_completed, 10'000u);
        EXPECT_EQ(n_sparse, q.stats.sparse_pixels);
        EXPECT_EQ(n_completed, q.stats.completed_pixels);
    }
}

// The z-buffer alone (no filter, no completion) equals a brute-force double-precision renderer, except where
// float rounding makes the two legitimately differ (a point within 1e-3 px of a pixel border, or depths
// equal to 1e-5).
TEST(QuasiRenderer, ZBufferMatchesBruteForceReference)
{
    const map::LidarMap& map = smallRoom();
    const core::CameraModel cam = eurocCam0();
    quasi::QuasiOptions o;
    o.occlusion_radius_px = 0;
    o.completion_radius_px = 0;
    quasi::QuasiRenderer renderer(map, o);
    const CPose3D T = cameraPose(0.3, -0.2, 1.4, -1.0, 0.25);
    quasi::QuasiImage q;
    renderer.render(T, cam, q);

    const int W = cam.width, H = cam.height;
    std::vector<std::pair<double, int32_t>> ref(size_t(W) * H, {1e300, -1});
    std::vector<Eigen::Vector2d> ref_px(ref.size());
    for (size_t i = 0; i < map.size(); ++i)
    {
        const Eigen::Vector3d p = toCam(T, map.point(i));
        Eigen::Vector2d px;
        if (p.z() < o.min_depth_m || p.z() > o.max_depth_m || !cam.project(p, px) || !cam.isInImage(px)) continue;
        const size_t k = size_t(std::floor(px.y() + 0.5)) * W + size_t(std::floor(px.x() + 0.5));
        if (std::make_pair(p.z(), int32_t(i)) < ref[k]) ref[k] = {p.z(), int32_t(i)}, ref_px[k] = px;
    }
    size_t agree = 0, explained = 0, hits = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
        {
            const size_t k = size_t(y) * W + x;
            const int32_t got = q.provenance.at<int32_t>(y, x);
            hits += ref[k].second >= 0;
            if (got == ref[k].second)
            {
                ++agree;
                continue;
            }
            // A disagreement must be a rounding tie.
            bool border = false, depth_tie = false;
            if (ref[k].second >= 0)
            {
                const Eigen::Vector2d f = ref_px[k] - Eigen::Vector2d(x, y);
                border = std::abs(std::abs(f.x()) - 0.5) < 1e-3 || std::abs(std::abs(f.y()) - 0.5) < 1e-3;
            }
            if (got >= 0 && ref[k].second >= 0)
                depth_tie = std::abs(toCam(T, map.point(got)).z() - ref[k].first) < 1e-5 * ref[k].first;
            if (got >= 0 && !border)
            {
                // The renderer's winner may sit on the border and belong here in float only.
                Eigen::Vector2d px;
                cam.project(toCam(T, map.point(got)), px);
                const Eigen::Vector2d f = px - Eigen::Vector2d(x, y);
                border = std::abs(std::abs(f.x()) - 0.5) < 1e-3 || std::abs(std::abs(f.y()) - 0.5) < 1e-3;
            }
            EXPECT_TRUE(border || depth_tie)
                << "pixel (" << x << ", " << y << "): renderer " << got << ", reference " << ref[k].second;
            ++explained;
        }
    EXPECT_GT(hits, 40'000u);
    EXPECT_LT(explained, 0.001 * hits);
    EXPECT_EQ(agree + explained, size_t(W) * H);
}

// (b) A near wall hides a far one, even where the near wall's points leave gaps that the far wall's points
// fall into (the see-through filter).
TEST(QuasiRenderer, NearWallHidesFarWall)
{
    const core::CameraModel cam = eurocCam0();
    const CPose3D T = cameraPose(0.5, 1.0, 1.5, 0.3, 0.1);
    map::LidarMap m;
    // Near wall: x in [-0.5, 0.5], y in [-0.4, 0.4] at z = 2 m; 0.8 cm spacing (~1.8 px at 2 m: gaps).
    const size_t n_near = addCameraPlane(m, T, -0.5, 0.5, -0.4, 0.4, 2.0, 0.008f, quasi::constantPattern(0.8f), 1);
    // Far wall filling the view at z = 6 m (2 cm spacing: ~1.5 px, so its points fall into the gaps).
    addCameraPlane(m, T, -8, 8, -5, 5, 6.0, 0.02f, quasi::constantPattern(0.2f), 2);
    // Near wall's image region, shrunk by a margin (completion and distortion at its edges).
    auto pixelOf = [&](double X, double Y, double Z) {
        Eigen::Vector2d px;
        cam.project({X, Y, Z}, px);
        return px;
    };
    const Eigen::Vector2d a = pixelOf(-0.5, -0.4, 2.0), b = pixelOf(0.5, 0.4, 2.0);
    const int margin = 6;
    const cv::Rect inner(int(a.x()) + margin, int(a.y()) + margin, int(b.x() - a.x()) - 2 * margin,
                         int(b.y() - a.y()) - 2 * margin);
    ASSERT_GT(inner.area(), 20'000);

    auto countFar = [&](const quasi::QuasiImage& q, cv::Rect r, size_t& valid) {
        size_t far = 0;
        valid = 0;
        for (int y = r.y; y < r.br().y; ++y)
            for (int x = r.x; x < r.br().x; ++x)
            {
                const int32_t idx = q.provenance.at<int32_t>(y, x);
                if (idx < 0) continue;
                ++valid;
                far += size_t(idx) >= n_near;
            }
        return far;
    };

    // Without the filter the far wall shows through the gaps: the scene does test the filter.
    quasi::QuasiOptions raw;
    raw.occlusion_radius_px = 0;
    raw.completion_radius_px = 0;
    quasi::QuasiRenderer raw_renderer(m, raw);
    quasi::QuasiImage q;
    raw_renderer.render(T, cam, q);
    size_t valid = 0;
    EXPECT_GT(countFar(q, inner, valid), 1000u);

    quasi::QuasiOptions o;  // defaults: filter and completion on
    quasi::QuasiRenderer renderer(m, o);
    renderer.render(T, cam, q);
    EXPECT_EQ(countFar(q, inner, valid), 0u);
    for (int y = inner.y; y < inner.br().y; ++y)
        for (int x = inner.x; x < inner.br().x; ++x) ASSERT_NEAR(q.depth.at<float>(y, x), 2.0f, 1e-4f);
    // Outside the near wall (beyond the margin) the far wall is still seen.
    const cv::Rect left(10, 10, std::max(1, int(a.x()) - 20), cam.height - 20);
    size_t valid_left = 0;
    EXPECT_EQ(countFar(q, left, valid_left), valid_left);
    EXPECT_GT(valid_left, 1000u);
}

// (c) Completion never mixes the two sides of a depth step: with fronto-parallel sides, every completed depth
// is one of the two depths.
TEST(QuasiRenderer, CompletionNeverCrossesDepthStep)
{
    const core::CameraModel cam = eurocCam0();
    const CPose3D T = cameraPose(-1.0, 0.5, 1.2, 1.1, -0.05);
    for (const int radius : {2, 4})
    {
        map::LidarMap m;
        // Left half at 2.0 m, right half at 2.6 m (30 % step): sparse enough (1.4 cm: ~3 px at 2 m) that most
        // pixels near the step are completed. Same reflectivity pattern on both sides, so reflectivity
        // consistency alone would not separate them.
        addCameraPlane(m, T, -2.0, 0.0, -1.5, 1.5, 2.0, 0.014f, quasi::checkerPattern(0.1f), 3);
        addCameraPlane(m, T, 0.0, 3.0, -2.0, 2.0, 2.6, 0.018f, quasi::checkerPattern(0.1f), 4);
        quasi::QuasiOptions o;
        o.completion_radius_px = radius;
        quasi::QuasiRenderer renderer(m, o);
        quasi::QuasiImage q;
        renderer.render(T, cam, q);
        size_t completed = 0, completed_near_step = 0;
        Eigen::Vector2d step_px;
        cam.project({0.0, 0.0, 2.0}, step_px);
        for (int y = 0; y < q.height(); ++y)
            for (int x = 0; x < q.width(); ++x)
            {
                if (!q.valid.at<uint8_t>(y, x)) continue;
                const float d = q.depth.at<float>(y, x);
                ASSERT_TRUE(std::abs(d - 2.0f) < 1e-4f || std::abs(d - 2.6f) < 1e-4f)
                    << "pixel (" << x << ", " << y << ") depth " << d << " radius " << radius;
                if (!q.sparse.at<uint8_t>(y, x))
                {
                    ++completed;
                    completed_near_step += std::abs(x - step_px.x()) < radius + 2;
                }
            }
        EXPECT_GT(completed, 50'000u);
        EXPECT_GT(completed_near_step, 100u);
    }
}

// (d) The same pose reached through another frame chain gives the identical image; so do repeated renders
// and another thread count (the z-buffer merge does not depend on scheduling).
TEST(QuasiRenderer, IdenticalThroughFrameChainsAndThreads)
{
    const map::LidarMap& map = smallRoom();
    const core::CameraModel cam = eurocCam0();
    const CPose3D T_world_cam = cameraPose(0.2, 0.1, 1.5, 2.0, 0.2);
    const CPose3D T_world_body(0.7, -1.3, 0.4, 0.9, -0.3, 0.2);
    const CPose3D T_body_cam = (-T_world_body) + T_world_cam;
    const CPose3D chained = T_world_body + T_body_cam;
    EXPECT_LT((chained.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>() -
               T_world_cam.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>())
                  .array()
                  .abs()
                  .maxCoeff(),
              1e-12);

    quasi::QuasiOptions o;
    quasi::QuasiRenderer renderer(map, o);
    quasi::QuasiImage a, b, c;
    renderer.render(T_world_cam, cam, a);
    renderer.render(chained, cam, b);
    EXPECT_TRUE(sameQuasi(a, b));
    renderer.render(T_world_cam, cam, c);
    EXPECT_TRUE(sameQuasi(a, c));

    o.num_threads = 1;
    quasi::QuasiRenderer single(map, o);
    single.render(chained, cam, c);
    EXPECT_TRUE(sameQuasi(a, c));
    o.num_threads = 3;
    quasi::QuasiRenderer three(map, o);
    three.render(T_world_cam, cam, c);
    EXPECT_TRUE(sameQuasi(a, c));
    EXPECT_GT(cv::countNonZero(a.valid), 100'000);
}

// The tracker's render (encode = false): the planes of the full render, bit for bit, and no encoded images; a
// full render after it encodes again.
TEST(QuasiRenderer, PlanesOnlyRenderHasTheFullRendersPlanes)
{
    const core::CameraModel cam = eurocCam0();
    const CPose3D T_world_cam = cameraPose(0.2, 0.1, 1.5, 2.0, 0.2);
    quasi::QuasiRenderer renderer(smallRoom(), quasi::QuasiOptions{});
    quasi::QuasiImage full, planes, again;
    renderer.render(T_world_cam, cam, full);
    renderer.render(T_world_cam, cam, planes, false);
    EXPECT_TRUE(planes.bgr.empty());
    EXPECT_TRUE(planes.gray.empty());
    EXPECT_TRUE(sameMat(full.depth, planes.depth) && sameMat(full.reflectivity, planes.reflectivity) &&
                sameMat(full.valid, planes.valid) && sameMat(full.sparse, planes.sparse) &&
                sameMat(full.provenance, planes.provenance));
    EXPECT_EQ(planes.stats.sparse_pixels, full.stats.sparse_pixels);
    EXPECT_GT(planes.stats.sparse_pixels, 10'000u);
    renderer.render(T_world_cam, cam, again);
    EXPECT_TRUE(sameQuasi(full, again));
}

// A render's own completion radius (the tracker's half-resolution edge model) gives what a renderer built with
// that radius gives, and the next render with the options' radius is the same as before it.
TEST(QuasiRenderer, CompletionRadiusOfOneRenderEqualsARendererBuiltWithIt)
{
    const core::CameraModel cam = eurocCam0().downscaled(2);
    const CPose3D T_world_cam = cameraPose(0.2, 0.1, 1.5, 2.0, 0.2);
    quasi::QuasiOptions o;
    o.completion_radius_px = 2;
    quasi::QuasiOptions o0 = o;
    o0.completion_radius_px = 0;
    quasi::QuasiRenderer renderer(smallRoom(), o), renderer0(smallRoom(), o0);
    quasi::QuasiImage with2, override0, built0, again2;
    renderer.render(T_world_cam, cam, with2, false);
    renderer.render(T_world_cam, cam, override0, false, 0);
    renderer0.render(T_world_cam, cam, built0, false);
    renderer.render(T_world_cam, cam, again2, false);
    EXPECT_TRUE(sameQuasi(override0, built0));
    EXPECT_TRUE(sameQuasi(with2, again2));
    EXPECT_GT(with2.stats.completed_pixels, override0.stats.completed_pixels);
    EXPECT_THROW(renderer.render(T_world_cam, cam, override0, false, 3), core::InputError);
}

// Rendering a pose from outside the room wall-on and from a pinhole camera works; bad input is rejected.
TEST(QuasiRenderer, RejectsBadInput)
{
    const map::LidarMap& map = smallRoom();
    quasi::QuasiOptions o;
    quasi::QuasiRenderer renderer(map, o);
    quasi::QuasiImage q;
    const CPose3D nan_pose(NAN, 0, 0, 0, 0, 0);
    EXPECT_THROW(renderer.render(nan_pose, eurocCam0(), q), core::InputError);
    core::CameraModel bad = eurocCam0();
    bad.fx = 0;
    EXPECT_THROW(renderer.render(cameraPose(0, 0, 1, 0, 0), bad, q), core::InputError);
    map::LidarMap empty;
    EXPECT_THROW(quasi::QuasiRenderer r(empty, o), core::InputError);
    o.completion_radius_px = -1;
    EXPECT_THROW(quasi::QuasiRenderer r(map, o), core::InputError);
}

// The renderer follows the camera it is given: a rectified pinhole model gives its own geometry.
TEST(QuasiRenderer, RendersInTheGivenCameraGeometry)
{
    const map::LidarMap& map = smallRoom();
    quasi::QuasiOptions o;
    quasi::QuasiRenderer renderer(map, o);
    const core::CameraModel pinhole = core::CameraModel::pinhole(320, 240, 250, 250, 160, 120);
    const CPose3D T = cameraPose(0, 0, 1.4, 0.3, 0.1);
    quasi::QuasiImage q;
    renderer.render(T, pinhole, q);
    ASSERT_EQ(q.width(), 320);
    ASSERT_EQ(q.height(), 240);
    size_t checked = 0;
    for (int y = 0; y < 240; ++y)
        for (int x = 0; x < 320; ++x)
        {
            if (!q.sparse.at<uint8_t>(y, x)) continue;
            Eigen::Vector2d px;
            ASSERT_TRUE(pinhole.project(toCam(T, map.point(q.provenance.at<int32_t>(y, x))), px));
            ASSERT_LE(std::max(std::abs(px.x() - x), std::abs(px.y() - y)), 0.5 + 1e-3);
            ++checked;
        }
    EXPECT_GT(checked, 30'000u);
    // And back to the distorted camera: buffers follow the size change.
    renderer.render(T, eurocCam0(), q);
    EXPECT_EQ(q.width(), 752);
}
