// The classical dense map computed in reusable scratch images must equal, bit for bit, the map as first written
// (fresh images, cv::merge), whatever the scratch held before.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <quasiloc/frontend/features.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <quasiloc/quasi/synthetic_scene.h>

#include "test_scenes.h"

using namespace quasiloc;
using namespace quasiloc::frontend;

namespace
{
/** The first version of computeGradientDenseMap. */
DenseMap plainGradientDenseMap(const cv::Mat& gray)
{
    constexpr int kBins = 8;
    cv::Mat half, gx, gy;
    cv::resize(gray, half, cv::Size(gray.cols / 4, gray.rows / 4), 0, 0, cv::INTER_AREA);
    half.convertTo(half, CV_32F, 1.0 / 255.0);
    cv::Sobel(half, gx, CV_32F, 1, 0, 3);
    cv::Sobel(half, gy, CV_32F, 0, 1, 3);
    const int H = half.rows, W = half.cols;
    std::vector<cv::Mat> bins(kBins);
    for (auto& b : bins) b = cv::Mat::zeros(H, W, CV_32F);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
        {
            const float ux = gx.at<float>(y, x), uy = gy.at<float>(y, x);
            const float mag = std::sqrt(ux * ux + uy * uy);
            if (mag < 1e-4f) continue;
            float a = std::atan2(uy, ux);
            if (a < 0) a += float(M_PI);
            const float f = a / float(M_PI) * kBins;
            const int b0 = int(f) % kBins, b1 = (b0 + 1) % kBins;
            const float t = f - std::floor(f);
            bins[b0].at<float>(y, x) += (1 - t) * mag;
            bins[b1].at<float>(y, x) += t * mag;
        }
    std::vector<cv::Mat> channels;
    for (double sigma : {1.0, 2.0})
        for (const auto& b : bins)
        {
            cv::Mat pooled;
            cv::GaussianBlur(b, pooled, cv::Size(0, 0), sigma, sigma, cv::BORDER_REFLECT);
            channels.push_back(pooled);
        }
    cv::Mat merged;
    cv::merge(channels, merged);
    DenseMap m;
    m.data = merged.reshape(1, H * W).clone();
    m.cols_cells = W;
    m.rows_cells = H;
    m.stride = double(gray.cols) / W;
    m.offset = 0.5 * m.stride - 0.5;
    for (int r = 0; r < m.data.rows; ++r)
    {
        float* v = m.data.ptr<float>(r);
        double n2 = 0;
        for (int c = 0; c < m.data.cols; ++c) n2 += double(v[c]) * v[c];
        if (n2 < 1e-12) continue;
        const float inv = float(1.0 / std::sqrt(n2));
        for (int c = 0; c < m.data.cols; ++c) v[c] *= inv;
    }
    return m;
}

void expectSameMap(const DenseMap& a, const DenseMap& b)
{
    ASSERT_EQ(a.data.size(), b.data.size());
    ASSERT_EQ(a.data.type(), b.data.type());
    EXPECT_EQ(cv::norm(a.data, b.data, cv::NORM_INF), 0.0);
    EXPECT_EQ(a.cols_cells, b.cols_cells);
    EXPECT_EQ(a.rows_cells, b.rows_cells);
    EXPECT_EQ(a.stride, b.stride);
    EXPECT_EQ(a.offset, b.offset);
}
}  // namespace

TEST(DenseMap, ScratchVersionEqualsThePlainOne)
{
    quasi::QuasiRenderer r(quasi::makeSyntheticRoom(300'000), quasi::QuasiOptions{});
    quasi::QuasiImage q;
    r.render(test::cameraPose(0.3, -0.2, 1.4, 0.4), test::testCamera(), q);
    // Different sizes one after the other through one scratch, then again.
    const std::vector<cv::Mat> images{test::texturedImage(640, 480, 3), q.gray, test::texturedImage(752, 480, 4),
                                      test::texturedImage(203, 157, 5), test::texturedImage(640, 480, 6)};
    DenseMapScratch scratch;
    for (int round = 0; round < 2; ++round)
        for (const auto& img : images)
        {
            const DenseMap expected = plainGradientDenseMap(img);
            expectSameMap(computeGradientDenseMap(img, scratch), expected);
            expectSameMap(computeGradientDenseMap(img), expected);
        }
}

TEST(DenseMap, ResultsDoNotShareTheScratch)
{
    DenseMapScratch scratch;
    const DenseMap a = computeGradientDenseMap(test::texturedImage(640, 480, 8), scratch);
    const cv::Mat a_copy = a.data.clone();
    computeGradientDenseMap(test::texturedImage(640, 480, 9), scratch);
    EXPECT_EQ(cv::norm(a.data, a_copy, cv::NORM_INF), 0.0);
}
