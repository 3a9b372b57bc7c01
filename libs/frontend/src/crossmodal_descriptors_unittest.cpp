// Cross-modal descriptors: what each promises (crossmodal_descriptors.h) on synthetic images: MIND-SSC and the
// orientation field are the same for an image and its inversion, the orientation field ignores the gradient's sign
// where NCC does not, every descriptor finds a shifted image at its shift, rank equalisation ignores monotone
// changes per range band, the depth-edge channel keeps steps and drops planes.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <quasiloc/frontend/crossmodal_descriptors.h>
#include <random>

using namespace quasiloc::frontend;

namespace
{
/** Smoothed random texture, 8-bit, full range. */
cv::Mat texture(int w, int h, uint32_t seed, double sigma = 2.0)
{
    cv::Mat f(h, w, CV_32F);
    cv::RNG rng(seed);
    rng.fill(f, cv::RNG::UNIFORM, 0.0, 1.0);
    cv::GaussianBlur(f, f, cv::Size(), sigma);
    cv::normalize(f, f, 0, 255, cv::NORM_MINMAX);
    cv::Mat u8;
    f.convertTo(u8, CV_8U);
    return u8;
}

const DescriptorKind kKinds[] = {DescriptorKind::Ncc, DescriptorKind::Mind, DescriptorKind::OrientationField};

std::vector<float> describe(const DescriptorField& d, int x, int y)
{
    std::vector<float> v(size_t(d.dims()));
    EXPECT_TRUE(d.describe(x, y, v.data())) << toString(d.kind) << " at " << x << ", " << y;
    return v;
}

float distanceAt(const DescriptorField& a, int xa, int ya, const DescriptorField& b, int xb, int yb)
{
    const auto u = describe(a, xa, ya), v = describe(b, xb, yb);
    return std::sqrt(squaredDistance(u.data(), v.data(), a.dims()));
}
}  // namespace

TEST(CrossModalDescriptors, MindAndOrientationFieldIgnoreInversion)
{
    const cv::Mat img = texture(120, 90, 1);
    const cv::Mat inv = 255 - img;
    const CrossModalDescriptorOptions o;
    for (DescriptorKind k : {DescriptorKind::Mind, DescriptorKind::OrientationField})
    {
        const DescriptorField a = computeDescriptorField(img, k, o), b = computeDescriptorField(inv, k, o);
        for (int y = 20; y < 70; y += 7)
            for (int x = 20; x < 100; x += 9) EXPECT_LT(distanceAt(a, x, y, b, x, y), 1e-3) << toString(k);
    }
    // NCC is not: an inverted patch is its opposite (distance 2).
    const DescriptorField a = computeDescriptorField(img, DescriptorKind::Ncc, o),
                          b = computeDescriptorField(inv, DescriptorKind::Ncc, o);
    EXPECT_GT(distanceAt(a, 60, 45, b, 60, 45), 1.9);
}

TEST(CrossModalDescriptors, OrientationFieldIgnoresGradientSign)
{
    // Folding the intensities about mid-grey flips the gradient's sign wherever the image is darker than it and
    // keeps its orientation: the orientation field stays close, NCC does not.
    const cv::Mat img = texture(120, 90, 2, 3.0);
    cv::Mat folded;
    cv::absdiff(img, cv::Scalar(128), folded);
    folded *= 2;
    const CrossModalDescriptorOptions o;
    const DescriptorField ao = computeDescriptorField(img, DescriptorKind::OrientationField, o),
                          bo = computeDescriptorField(folded, DescriptorKind::OrientationField, o);
    const DescriptorField an = computeDescriptorField(img, DescriptorKind::Ncc, o),
                          bn = computeDescriptorField(folded, DescriptorKind::Ncc, o);
    double orient = 0, ncc = 0, unrelated = 0;
    int n = 0;
    for (int y = 20; y < 70; y += 5)
        for (int x = 20; x < 100; x += 5, ++n)
        {
            orient += distanceAt(ao, x, y, bo, x, y);
            ncc += distanceAt(an, x, y, bn, x, y);
            unrelated += distanceAt(ao, x, y, bo, 120 - x, 90 - y);
        }
    orient /= n, ncc /= n, unrelated /= n;
    EXPECT_LT(orient, 0.35);
    EXPECT_GT(ncc, 2.5 * orient);
    EXPECT_GT(unrelated, 3 * orient);

    // Orientation itself is kept: vertical and horizontal stripes differ.
    cv::Mat vertical(60, 60, CV_8U), horizontal;
    for (int y = 0; y < 60; ++y)
        for (int x = 0; x < 60; ++x) vertical.at<uint8_t>(y, x) = uint8_t(127 + 100 * std::sin(x * 0.8));
    cv::transpose(vertical, horizontal);
    const DescriptorField v = computeDescriptorField(vertical, DescriptorKind::OrientationField, o),
                          h = computeDescriptorField(horizontal, DescriptorKind::OrientationField, o);
    EXPECT_GT(distanceAt(v, 30, 30, h, 30, 30), 1.0);
}

TEST(CrossModalDescriptors, ShiftedImageMatchesAtTheShift)
{
    const cv::Mat img = texture(140, 110, 3);
    const cv::Point shift(7, -4);
    cv::Mat moved;
    const cv::Mat M = (cv::Mat_<double>(2, 3) << 1, 0, shift.x, 0, 1, shift.y);
    cv::warpAffine(img, moved, M, img.size(), cv::INTER_NEAREST, cv::BORDER_REFLECT);
    const CrossModalDescriptorOptions o;
    for (DescriptorKind k : kKinds)
    {
        const DescriptorField a = computeDescriptorField(img, k, o), b = computeDescriptorField(moved, k, o);
        int found = 0, tried = 0;
        for (int y = 35; y <= 75; y += 10)
            for (int x = 35; x <= 105; x += 10, ++tried)
            {
                const auto u = describe(a, x, y);
                std::vector<float> v(size_t(b.dims()));
                float best = 1e9f;
                cv::Point at;
                for (int dy = -10; dy <= 10; ++dy)
                    for (int dx = -10; dx <= 10; ++dx)
                        if (b.describe(x + dx, y + dy, v.data()))
                        {
                            const float d = squaredDistance(u.data(), v.data(), b.dims());
                            if (d < best) best = d, at = {dx, dy};
                        }
                found += at == shift;
            }
        EXPECT_EQ(found, tried) << toString(k);
    }
}

TEST(CrossModalDescriptors, RankEqualisationPerRangeBand)
{
    // Two range bands (2 m and 20 m) with the same texture at different levels, one pixel invalid.
    const cv::Mat t = texture(40, 20, 4);
    cv::Mat values(20, 40, CV_32F), depth(20, 40, CV_32F), valid(20, 40, CV_8U, cv::Scalar(255));
    for (int y = 0; y < 20; ++y)
        for (int x = 0; x < 40; ++x)
        {
            const bool far = x >= 20;
            values.at<float>(y, x) = t.at<uint8_t>(y, x) / 255.f * (far ? 0.2f : 1.f);
            depth.at<float>(y, x) = far ? 20.f : 2.f;
        }
    valid.at<uint8_t>(5, 5) = 0;
    const cv::Mat one = rankEqualised(values, valid), banded = rankEqualised(values, valid, depth, 2);
    cv::Mat exp_values;
    cv::exp(values * 3, exp_values);
    const cv::Mat banded_exp = rankEqualised(exp_values, valid, depth, 2);
    EXPECT_EQ(one.at<float>(5, 5), 0.f);
    EXPECT_LT(cv::norm(banded, banded_exp, cv::NORM_INF), 1e-6);  // monotone changes do not matter
    double lo_near = 1, hi_near = 0, lo_far = 1, hi_far = 0, max_one_far = 0;
    for (int y = 0; y < 20; ++y)
        for (int x = 0; x < 40; ++x)
        {
            if (!valid.at<uint8_t>(y, x)) continue;
            const double r = banded.at<float>(y, x);
            (x < 20 ? lo_near : lo_far) = std::min(x < 20 ? lo_near : lo_far, r);
            (x < 20 ? hi_near : hi_far) = std::max(x < 20 ? hi_near : hi_far, r);
            if (x >= 20) max_one_far = std::max<double>(max_one_far, one.at<float>(y, x));
        }
    // Each band spans [0, 1] on its own; with one band the dim far half stays low.
    EXPECT_EQ(lo_near, 0);
    EXPECT_EQ(hi_near, 1);
    EXPECT_EQ(lo_far, 0);
    EXPECT_EQ(hi_far, 1);
    EXPECT_LT(max_one_far, 0.6);
}

TEST(CrossModalDescriptors, DepthEdgeChannelKeepsStepsDropsPlanes)
{
    // A ground-like ramp (depth growing with the row) with a box in front on the left.
    cv::Mat depth(60, 80, CV_32F), valid(60, 80, CV_8U, cv::Scalar(255));
    for (int y = 0; y < 60; ++y)
        for (int x = 0; x < 80; ++x)
            depth.at<float>(y, x) = (x < 40 && y > 20 && y < 50) ? 3.f : 30.f / (1.f + 0.05f * float(y));
    const cv::Mat e = depthEdgeChannel(depth, valid, 2.0, 0.05);
    EXPECT_LT(std::abs(e.at<float>(10, 60)), 0.1);  // on the ramp
    EXPECT_LT(std::abs(e.at<float>(35, 20)), 0.1);  // inside the box
    EXPECT_GT(std::abs(e.at<float>(35, 39)), 0.8);  // at the box's edge
    EXPECT_GT(std::abs(e.at<float>(35, 40)), 0.8);
}

TEST(CrossModalDescriptors, LocalNormalisationIgnoresGainAndOffset)
{
    const cv::Mat img = texture(80, 60, 5);
    cv::Mat dim;
    img.convertTo(dim, CV_32F, 0.3, 20);
    const cv::Mat a = locallyNormalised(img, 5, 1e-3), b = locallyNormalised(dim, 5, 1e-3);
    EXPECT_LT(cv::norm(a, b, cv::NORM_INF), 1e-2);
    EXPECT_GT(cv::norm(a, cv::NORM_INF), 1.0);
}

TEST(CrossModalDescriptors, FillInvalidKeepsValidPixels)
{
    cv::Mat v(20, 20, CV_32F, cv::Scalar(0.5)), valid(20, 20, CV_8U, cv::Scalar(255));
    v(cv::Rect(8, 8, 4, 4)).setTo(0);
    valid(cv::Rect(8, 8, 4, 4)).setTo(0);
    v.at<float>(0, 0) = 0.9f;
    const cv::Mat f = fillInvalid(v, valid, 2.0);
    EXPECT_FLOAT_EQ(f.at<float>(0, 0), 0.9f);
    EXPECT_NEAR(f.at<float>(10, 10), 0.5, 0.01);
}
