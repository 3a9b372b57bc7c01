// Tests of the renderer's stages and options: SIMD completion equals the scalar reference, the projector
// does not let points from outside the field of view wrap into the image, INI handling.
#include <gtest/gtest.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <cstring>
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/quasi/histogram_matching.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <quasiloc/quasi/synthetic_scene.h>

#include "render_stages.h"

using namespace quasiloc;

namespace
{
/** Random sparse planes: two depth layers (step), random reflectivity, ~density of pixels hit. */
quasi::detail::SparsePlanes randomSparse(int W, int H, double density, uint32_t seed)
{
    quasi::detail::SparsePlanes p;
    p.create(W, H);
    cv::RNG rng(seed);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
        {
            if (rng.uniform(0.0, 1.0) > density)
            {
                p.depth.at<float>(y, x) = quasi::detail::kNoDepth;
                p.refl.at<float>(y, x) = 0;
                p.index.at<int32_t>(y, x) = -1;
                continue;
            }
            const bool far = (x + y / 3) % 40 > 20;
            p.depth.at<float>(y, x) = float((far ? 4.0 : 2.0) + rng.uniform(-0.05, 0.05));
            p.refl.at<float>(y, x) = float(rng.uniform(0.0, 1.0));
            p.index.at<int32_t>(y, x) = y * W + x;
        }
    return p;
}

void allocate(quasi::QuasiImage& q, int W, int H)
{
    q.depth.create(H, W, CV_32FC1);
    q.reflectivity.create(H, W, CV_32FC1);
    q.valid.create(H, W, CV_8UC1);
    q.sparse.create(H, W, CV_8UC1);
    q.provenance.create(H, W, CV_32SC1);
}

bool same(const cv::Mat& a, const cv::Mat& b)
{
    return a.size() == b.size() && a.type() == b.type() && std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
}
}  // namespace

TEST(QuasiStages, SimdCompletionEqualsScalarReference)
{
    const int W = 97, H = 61;
    for (const int radius : {1, 2, 3, 5})
        for (const double density : {0.15, 0.5})
        {
            const auto sparse = randomSparse(W, H, density, 7 + radius);
            quasi::QuasiOptions o;
            o.completion_radius_px = radius;
            o.completion_reflectivity_abs = 0.3;
            quasi::QuasiImage a, b;
            allocate(a, W, H);
            allocate(b, W, H);
            const size_t na = quasi::detail::completeRows(sparse, 0, H, o, a, true);
            const size_t nb = quasi::detail::completeRows(sparse, 0, H, o, b, false);
            EXPECT_EQ(na, nb);
            EXPECT_GT(na, 100u);
            EXPECT_TRUE(same(a.depth, b.depth)) << "radius " << radius << " density " << density;
            EXPECT_TRUE(same(a.reflectivity, b.reflectivity));
            EXPECT_TRUE(same(a.provenance, b.provenance));
            EXPECT_TRUE(same(a.valid, b.valid));
            // The renderer's planes carry an empty margin (every window readable): the same result.
            quasi::detail::SparsePlanes padded;
            padded.create(W, H, radius);
            sparse.depth.copyTo(padded.depth);
            sparse.refl.copyTo(padded.refl);
            sparse.index.copyTo(padded.index);
            quasi::QuasiImage c;
            allocate(c, W, H);
            EXPECT_EQ(quasi::detail::completeRows(padded, 0, H, o, c, true), nb);
            EXPECT_TRUE(same(c.depth, b.depth) && same(c.reflectivity, b.reflectivity) &&
                        same(c.provenance, b.provenance) && same(c.valid, b.valid) && same(c.sparse, b.sparse))
                << "with margin: radius " << radius << " density " << density;
        }
}

// Radius 0 (the tracker's half-resolution render): no completion, the output is the sparse planes, empty pixels
// zero with provenance -1; also with the renderer's margin.
TEST(QuasiStages, RadiusZeroCopiesTheSparsePlanes)
{
    const int W = 97, H = 61;
    const auto sparse = randomSparse(W, H, 0.3, 11);
    quasi::QuasiOptions o;
    o.completion_radius_px = 0;
    quasi::detail::SparsePlanes padded;
    padded.create(W, H, 2);
    sparse.depth.copyTo(padded.depth);
    sparse.refl.copyTo(padded.refl);
    sparse.index.copyTo(padded.index);
    for (const quasi::detail::SparsePlanes* planes :
         {&sparse, static_cast<const quasi::detail::SparsePlanes*>(&padded)})
    {
        quasi::QuasiImage q;
        allocate(q, W, H);
        EXPECT_EQ(quasi::detail::completeRows(*planes, 0, H, o, q), 0u);
        size_t hits = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x)
            {
                const int32_t i = sparse.index.at<int32_t>(y, x);
                const bool hit = i >= 0;
                hits += hit;
                ASSERT_EQ(q.provenance.at<int32_t>(y, x), hit ? i : -1);
                ASSERT_EQ(q.depth.at<float>(y, x), hit ? sparse.depth.at<float>(y, x) : 0.0f);
                ASSERT_EQ(q.reflectivity.at<float>(y, x), hit ? sparse.refl.at<float>(y, x) : 0.0f);
                ASSERT_EQ(q.valid.at<uint8_t>(y, x), hit ? 255 : 0);
                ASSERT_EQ(q.sparse.at<uint8_t>(y, x), hit ? 255 : 0);
            }
        EXPECT_GT(hits, 1000u);
    }
}

// Completed values follow the rule: reflectivity is a maximum of depth-consistent neighbours, depth lies within
// the depth tolerance of a neighbour (never between the layers), provenance is a window neighbour.
TEST(QuasiStages, CompletionFollowsTheRule)
{
    const int W = 80, H = 50, R = 2;
    const auto sparse = randomSparse(W, H, 0.3, 3);
    quasi::QuasiOptions o;
    o.completion_radius_px = R;
    quasi::QuasiImage q;
    allocate(q, W, H);
    quasi::detail::completeRows(sparse, 0, H, o, q);
    size_t checked = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
        {
            if (!q.valid.at<uint8_t>(y, x) || q.sparse.at<uint8_t>(y, x)) continue;
            const int32_t idx = q.provenance.at<int32_t>(y, x);
            ASSERT_GE(idx, 0);
            const int px = idx % W, py = idx / W;
            ASSERT_LE(std::max(std::abs(px - x), std::abs(py - y)), R);
            const float d = q.depth.at<float>(y, x);
            ASSERT_TRUE((d > 1.9f && d < 2.1f) || (d > 3.9f && d < 4.1f)) << d;
            // The reflectivity is one of the window's values.
            bool found = false;
            for (int yy = std::max(0, y - R); yy <= std::min(H - 1, y + R); ++yy)
                for (int xx = std::max(0, x - R); xx <= std::min(W - 1, x + R); ++xx)
                    found |= sparse.index.at<int32_t>(yy, xx) >= 0 &&
                             sparse.refl.at<float>(yy, xx) == q.reflectivity.at<float>(y, x);
            ASSERT_TRUE(found);
            ++checked;
        }
    EXPECT_GT(checked, 1000u);
}

// A strongly distorted lens: points far outside the field of view, which the radial polynomial would fold
// back into the image, are rejected.
TEST(QuasiStages, ProjectorRejectsFoldedPoints)
{
    core::CameraModel cam = core::CameraModel::pinhole(640, 480, 400, 400, 320, 240);
    cam.model = core::DistortionModel::RadTan;
    cam.dist = {-0.1, 0, 0, 0, 0};  // r*(1 - 0.1 r^2) folds at r = 1.83; r = 3 maps to 0.3 (inside the image)
    const auto proj = quasi::detail::FastProjector::fromCamera(cam);
    map::LidarMap m;
    for (int i = 0; i < 2000; ++i)
    {
        const double a = i * 2 * M_PI / 2000, r = 2.5 + (i % 10) * 0.1;  // normalised radius 2.5..3.4
        m.addPoint(float(r * std::cos(a)), float(r * std::sin(a)), 1.0f, 0.5f);
        m.addPoint(float(0.3 * std::cos(a)), float(0.3 * std::sin(a)), 1.0f, 0.5f);  // inside: kept
    }
    const map::VisibilityIndex index(m, {});
    const std::vector<map::VisibilityIndex::Range> all{{0, uint32_t(index.size())}};
    quasi::detail::ZBuffer zb;
    zb.key.assign(640 * 480, quasi::detail::kEmptyKey);
    zb.refl.assign(640 * 480, 0.f);
    const auto pose = quasi::detail::PoseF::camFromWorld(mrpt::poses::CPose3D());
    quasi::detail::projectPoints(index, all, 0, index.size(), proj, pose, 0.1f, 100.f, zb);
    EXPECT_EQ(zb.projected, 2000u);  // only the inner ring
    for (size_t p = 0; p < zb.key.size(); ++p)
    {
        if (zb.key[p] != quasi::detail::kEmptyKey)
        {
            ASSERT_EQ(uint32_t(zb.key[p]) % 2, 1u);  // odd indices: the inner ring
        }
    }
}

TEST(QuasiOptions, IniRoundTripAndRejections)
{
    quasi::QuasiOptions o;
    o.completion_radius_px = 4;
    o.gray_mode = quasi::GrayMode::Value;
    o.reflectivity_scope = "map";
    mrpt::config::CConfigFileMemory written;
    o.saveToConfigFile(written, "QuasiImage");
    const mrpt::config::CConfigFileMemory cfg(written.getContent());  // re-parsed from text, as a program reads it
    quasi::QuasiOptions back;
    core::loadOptionsChecked(back, cfg, "QuasiImage", "test.ini");
    EXPECT_EQ(back.completion_radius_px, 4);
    EXPECT_EQ(back.gray_mode, quasi::GrayMode::Value);
    EXPECT_EQ(back.reflectivityScope(), quasi::ReflectivityScope::Map);
    EXPECT_NO_THROW(back.check("test.ini"));

    auto loadError = [](const std::string& text) {
        quasi::QuasiOptions q;
        try
        {
            core::loadOptionsChecked(q, mrpt::config::CConfigFileMemory(text), "QuasiImage", "test.ini");
        }
        catch (const core::InputError& e)
        {
            return std::string(e.what());
        }
        return std::string();
    };
    // A typo'd key, a value that is not a number, a mode name, a value out of range: each names the key.
    EXPECT_NE(
        loadError("[QuasiImage]\ncompletion_radius = 3\n").find("test.ini [QuasiImage] completion_radius: unknown key"),
        std::string::npos);
    EXPECT_NE(loadError("[QuasiImage]\ncompletion_depth_rel = abc\n").find("[QuasiImage] completion_depth_rel"),
              std::string::npos);
    EXPECT_NE(loadError("[QuasiImage]\nedge_operator = sobel\n").find("'sobel' is not one of gradient, laplacian"),
              std::string::npos);
    EXPECT_NE(loadError("[QuasiImage]\nreflectivity_scope = world\n").find("'world' is not one of image, map"),
              std::string::npos);
    EXPECT_NE(loadError("[QuasiImage]\nocclusion_max_gap_deg = 180\n").find("must be (0, 180)"), std::string::npos);
    quasi::QuasiOptions wrong;
    wrong.value_gain = 0.9;  // b1 + b2 > 1
    EXPECT_THROW(wrong.check("test.ini"), core::InputError);
    wrong = quasi::QuasiOptions{};
    wrong.completion_radius_px = 16;  // set in code: the declared range still holds
    EXPECT_THROW(wrong.check("test.ini"), core::InputError);
    wrong = quasi::QuasiOptions{};
    wrong.reflectivity_scope = "world";
    try
    {
        wrong.check("test.ini");
        ADD_FAILURE() << "reflectivity_scope = world accepted";
    }
    catch (const core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("test.ini [QuasiImage] reflectivity_scope: the present value is not one "
                                             "of image, map"),
                  std::string::npos)
            << e.what();
    }
}

TEST(Splatting, NearPointsCoverTheirFootprintAndStripesAgree)
{
    const int W = 160, H = 120;
    const auto src = randomSparse(W, H, 0.05, 11);  // layers at 2 m and 4 m, 5 % of the pixels hit
    // Footprint radius = radius_px_at_1m / z: 3 px at 2 m, 1 px at 4 m.
    const float radius_px_at_1m = 6.5f;
    auto whole = src;
    whole.depth = src.depth.clone(), whole.refl = src.refl.clone(), whole.index = src.index.clone();
    const size_t covered = quasi::detail::splatRows(src, 0, H, radius_px_at_1m, 6, whole);
    EXPECT_GT(covered, size_t(W * H / 4)) << "splats must fill most holes";
    // Every pixel shows the nearest point whose square covers it (brute force).
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
        {
            float best = quasi::detail::kNoDepth;
            int best_index = -1;
            for (int ys = std::max(0, y - 6); ys < std::min(H, y + 7); ++ys)
                for (int xs = std::max(0, x - 6); xs < std::min(W, x + 7); ++xs)
                {
                    const float z = src.depth.at<float>(ys, xs);
                    if (!(z < quasi::detail::kNoDepth)) continue;
                    const int r = std::min(6, int(radius_px_at_1m / z));
                    if (std::abs(ys - y) > r || std::abs(xs - x) > r) continue;
                    const int idx = src.index.at<int32_t>(ys, xs);
                    if (z < best || (z == best && idx < best_index)) best = z, best_index = idx;
                }
            ASSERT_EQ(whole.index.at<int32_t>(y, x), best_index) << "pixel " << x << "," << y;
            ASSERT_EQ(whole.depth.at<float>(y, x), best);
        }
    // Row stripes (as the renderer runs them in parallel) give the same image.
    auto striped = src;
    striped.depth = src.depth.clone(), striped.refl = src.refl.clone(), striped.index = src.index.clone();
    for (const auto& [y0, y1] : {std::pair{0, 37}, std::pair{37, 38}, std::pair{38, 90}, std::pair{90, H}})
        quasi::detail::splatRows(src, y0, y1, radius_px_at_1m, 6, striped);
    EXPECT_EQ(cv::norm(whole.index, striped.index, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(whole.refl, striped.refl, cv::NORM_INF), 0.0);
}

TEST(Splatting, RendererFillsACloseSparseWall)
{
    // The synthetic room thinned to 60k points seen from 1 m: single-pixel points leave most of the image empty.
    const map::LidarMap map = quasi::makeSyntheticRoom(60000);
    const core::CameraModel camera = core::CameraModel::pinhole(752, 480, 458.0, 457.0, 367.0, 248.0);
    mrpt::poses::CPose3D T_world_cam(2.0, 0.0, 1.3, -M_PI / 2, 0, -M_PI / 2);  // looking along +x at the wall
    quasi::QuasiOptions o;
    o.completion_radius_px = 0;
    o.occlusion_radius_px = 0;
    quasi::QuasiImage plain, splatted;
    quasi::QuasiRenderer(map, o).render(T_world_cam, camera, plain);
    o.point_size_m = 0.05;
    quasi::QuasiRenderer(map, o).render(T_world_cam, camera, splatted);
    const double f_plain = cv::countNonZero(plain.valid) / double(plain.valid.total());
    const double f_splat = cv::countNonZero(splatted.valid) / double(splatted.valid.total());
    std::printf("valid pixels: %.1f %% one pixel per point, %.1f %% splatted (%zu splatted pixels)\n", 100 * f_plain,
                100 * f_splat, splatted.stats.splatted_pixels);
    EXPECT_GT(f_splat, f_plain + 0.2);
    EXPECT_GT(splatted.stats.splatted_pixels, 0u);
    // Every valid pixel still lifts to a map point.
    for (int y = 0; y < splatted.height(); y += 7)
        for (int x = 0; x < splatted.width(); x += 7)
            if (splatted.valid.at<uint8_t>(y, x)) EXPECT_GE(splatted.provenance.at<int32_t>(y, x), 0);
}

TEST(ScanlineFill, FillsShortGapsWithinASurfaceOnly)
{
    // One column per case: valid rows 10 and 14 (a 3-row gap) at depths (2, 2.1): filled; at (2, 3): a depth step,
    // kept; valid rows 10 and 30 (19 rows): longer than the limit, kept.
    const int W = 3, H = 40;
    quasi::QuasiImage q;
    q.depth = cv::Mat::zeros(H, W, CV_32FC1);
    q.reflectivity = cv::Mat::zeros(H, W, CV_32FC1);
    q.valid = cv::Mat::zeros(H, W, CV_8UC1);
    q.provenance = cv::Mat(H, W, CV_32SC1, cv::Scalar(-1));
    auto set = [&](int y, int x, float d, float i, int32_t p) {
        q.depth.at<float>(y, x) = d, q.reflectivity.at<float>(y, x) = i, q.valid.at<uint8_t>(y, x) = 255;
        q.provenance.at<int32_t>(y, x) = p;
    };
    set(10, 0, 2.0f, 0.2f, 7), set(14, 0, 2.1f, 0.6f, 8);
    set(10, 1, 2.0f, 0.2f, 7), set(14, 1, 3.0f, 0.6f, 8);
    set(10, 2, 2.0f, 0.2f, 7), set(30, 2, 2.0f, 0.6f, 8);
    EXPECT_EQ(quasi::detail::fillScanlineGapColumns(q, 0, W, 8, 0.05), 3u);
    for (int y = 11; y <= 13; ++y)
    {
        ASSERT_TRUE(q.valid.at<uint8_t>(y, 0));
        const float t = float(y - 10) / 4.f;
        EXPECT_NEAR(1.f / q.depth.at<float>(y, 0), (1 - t) / 2.0f + t / 2.1f, 1e-6);  // inverse depth is linear
        EXPECT_NEAR(q.reflectivity.at<float>(y, 0), (1 - t) * 0.2f + t * 0.6f, 1e-6);
        EXPECT_EQ(q.provenance.at<int32_t>(y, 0), y <= 12 ? 7 : 8);  // the nearer end
        EXPECT_FALSE(q.valid.at<uint8_t>(y, 1));
    }
    for (int y = 11; y < 30; ++y) EXPECT_FALSE(q.valid.at<uint8_t>(y, 2));
}

TEST(ScanlineFill, RendererFillsTheGapsOfAThinnedSurface)
{
    // A wall whose map keeps every 6th row of points: without the fill its render is striped, with it the rows
    // between the stripes are valid (and no gap is filled across the wall's edge into the empty background).
    quasi::QuasiOptions o;
    o.completion_radius_px = 1;
    map::LidarMap wall;
    for (int r = 0; r < 120; r += 6)
        for (int c = 0; c < 200; ++c) wall.addPoint(float(-1.0 + c * 0.01), float(-0.6 + r * 0.01), 3.0f, 0.5f);
    core::CameraModel cam = core::CameraModel::pinhole(320, 240, 300, 300, 160, 120);
    quasi::QuasiImage without, with;
    quasi::QuasiRenderer(wall, o).render(mrpt::poses::CPose3D(), cam, without);
    o.scanline_gap_px = 8;
    quasi::QuasiRenderer(wall, o).render(mrpt::poses::CPose3D(), cam, with);
    const cv::Rect inner(100, 80, 120, 80);  // inside the wall's image
    EXPECT_LT(cv::countNonZero(without.valid(inner)), int(0.6 * inner.area()));
    EXPECT_EQ(cv::countNonZero(with.valid(inner)), inner.area());
    EXPECT_GT(with.stats.scanline_filled_pixels, 0u);
    EXPECT_EQ(cv::countNonZero(with.valid(cv::Rect(0, 0, 320, 20))), 0);  // above the wall: nothing to fill
}

TEST(HistogramMatching, RecoversAMonotoneRemappingAndIgnoresInvalidPixels)
{
    // The camera sees f(reflectivity) for a monotone f: the matched quasi-image must reproduce it. The invalid pixels
    // (where the camera shows something else, here saturated) neither take part nor get a value.
    const int W = 64, H = 48;
    quasi::QuasiImage q;
    q.reflectivity = cv::Mat::zeros(H, W, CV_32FC1);
    q.valid = cv::Mat::zeros(H, W, CV_8UC1);
    cv::Mat camera(H, W, CV_8UC1, cv::Scalar(255));
    cv::RNG rng(3);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
        {
            if (x < 8) continue;  // invalid: camera 255
            const float r = float(rng.uniform(0.0, 1.0));
            q.reflectivity.at<float>(y, x) = r;
            q.valid.at<uint8_t>(y, x) = 255;
            camera.at<uint8_t>(y, x) = uint8_t(std::lround(20 + 200 * std::sqrt(r)));
        }
    const cv::Mat matched = quasi::reflectivityMatchedToImage(q, camera);
    double worst = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
        {
            if (!q.valid.at<uint8_t>(y, x))
            {
                EXPECT_EQ(matched.at<uint8_t>(y, x), 0);
                continue;
            }
            worst = std::max(worst, std::abs(double(matched.at<uint8_t>(y, x)) - camera.at<uint8_t>(y, x)));
        }
    EXPECT_LE(worst, 8.0);  // 256 reflectivity bins: sqrt is steep near 0, one bin spans up to ~13 levels there
    // Mismatched sizes are an input error naming the step.
    EXPECT_THROW(quasi::reflectivityMatchedToImage(q, cv::Mat(H + 1, W, CV_8UC1)), core::InputError);
}
