// Tests of the renderer's stages and options: SIMD completion equals the scalar reference, the projector
// does not let points from outside the field of view wrap into the image, INI handling.
#include <gtest/gtest.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <cstring>
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
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
    return a.size() == b.size() && a.type() == b.type() &&
           std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
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
    o.gray_mode = "value";
    mrpt::config::CConfigFileMemory written;
    o.saveToConfigFile(written, "QuasiImage");
    // Re-parsed from text, as a program reads it (MRPT reads padded keys back only from text).
    const mrpt::config::CConfigFileMemory cfg(written.getContent());
    quasi::QuasiOptions back;
    core::loadOptionsChecked(back, cfg, "QuasiImage", "test.ini");
    EXPECT_EQ(back.completion_radius_px, 4);
    EXPECT_EQ(back.gray_mode, "value");
    EXPECT_NO_THROW(back.check("test.ini"));

    mrpt::config::CConfigFileMemory bad;
    bad.write("QuasiImage", "completion_radius", 3);  // unknown key
    EXPECT_THROW(core::loadOptionsChecked(back, bad, "QuasiImage", "test.ini"), core::InputError);
    mrpt::config::CConfigFileMemory typo;
    typo.write("QuasiImage", "completion_depth_rel", std::string("abc"));
    EXPECT_THROW(core::loadOptionsChecked(back, typo, "QuasiImage", "test.ini"), core::InputError);
    quasi::QuasiOptions wrong;
    wrong.edge_operator = "sobel";
    EXPECT_THROW(wrong.check("test.ini"), core::InputError);
    wrong = quasi::QuasiOptions{};
    wrong.value_gain = 0.9;  // b1 + b2 > 1
    EXPECT_THROW(wrong.check("test.ini"), core::InputError);
}
