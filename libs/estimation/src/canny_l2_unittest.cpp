// cannyL2 against cv::Canny with the L2 norm: the same edges on images of many sizes and contents, for thresholds
// of every kind (percentile ones as the edge field uses, swapped, zero, beyond OpenCV's clamp).
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <quasiloc/core/error.h>
#include <random>

#include "canny_l2.h"

using quasiloc::estimation::detail::cannyL2;

namespace
{
/** A scene-like 8-bit image: blurred rectangles, lines and circles over noise, then its 3x3 Sobel derivatives. */
void derivatives(int width, int height, unsigned seed, double noise, cv::Mat& dx, cv::Mat& dy)
{
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> u(0, 255);
    cv::Mat img(height, width, CV_8UC1, cv::Scalar(u(rng)));
    for (int i = 0; i < 12; ++i)
    {
        const cv::Point a(u(rng) % width, u(rng) % height), b(u(rng) % width, u(rng) % height);
        switch (i % 3)
        {
            case 0: cv::rectangle(img, a, b, cv::Scalar(u(rng)), cv::FILLED); break;
            case 1: cv::line(img, a, b, cv::Scalar(u(rng)), 1 + u(rng) % 3); break;
            default: cv::circle(img, a, 1 + u(rng) % std::max(1, width / 3), cv::Scalar(u(rng)), cv::FILLED);
        }
    }
    cv::Mat n(height, width, CV_8UC1);
    cv::randn(n, 0, noise);
    img += n;
    cv::GaussianBlur(img, img, cv::Size(3, 3), 0);
    cv::Sobel(img, dx, CV_16S, 1, 0, 3);
    cv::Sobel(img, dy, CV_16S, 0, 1, 3);
}

void expectSameAsOpenCv(const cv::Mat& dx, const cv::Mat& dy, double low, double high, const std::string& what)
{
    cv::Mat expected;
    cv::Canny(dx, dy, expected, low, high, true);
    for (const bool avx2 : {true, false})  // where the CPU has AVX2, both paths; else the four-pixel one twice
    {
        cv::Mat edges;
        cannyL2(dx, dy, low, high, edges, avx2);
        ASSERT_EQ(edges.type(), CV_8UC1) << what;
        ASSERT_EQ(edges.size(), expected.size()) << what;
        EXPECT_EQ(cv::countNonZero(edges != expected), 0)
            << what << ", low " << low << ", high " << high << (avx2 ? ", AVX2 if available" : ", four pixels");
    }
}
}  // namespace

TEST(CannyL2, SameEdgesAsOpenCvOnScenesOfManySizes)
{
    int compared = 0, with_edges = 0;
    for (const cv::Size size : {cv::Size(752, 480), cv::Size(376, 240), cv::Size(188, 120), cv::Size(101, 37),
                                cv::Size(33, 65), cv::Size(7, 5), cv::Size(5, 1), cv::Size(1, 6), cv::Size(2, 2)})
        for (unsigned seed = 0; seed < 4; ++seed)
        {
            cv::Mat dx, dy;
            derivatives(size.width, size.height, seed, seed % 2 ? 12.0 : 2.0, dx, dy);
            for (const double high : {30.0, 120.0, 400.0})
                for (const double ratio : {0.4, 0.1, 1.0})
                {
                    const std::string what = std::to_string(size.width) + " x " + std::to_string(size.height) +
                                             ", seed " + std::to_string(seed);
                    expectSameAsOpenCv(dx, dy, ratio * high, high, what);
                    cv::Mat edges;
                    cannyL2(dx, dy, ratio * high, high, edges);
                    with_edges += cv::countNonZero(edges) > 0;
                    ++compared;
                }
        }
    EXPECT_GT(with_edges, compared / 2) << "the comparison must be about images that have edges";
}

TEST(CannyL2, ThresholdsOfEveryKindAsOpenCvTakesThem)
{
    cv::Mat dx, dy;
    derivatives(160, 90, 7, 8.0, dx, dy);
    for (const auto& [low, high] : std::vector<std::pair<double, double>>{
             {200, 50}, {0, 0}, {0, 60}, {-5, 40}, {40, 40}, {33.7, 90.2}, {1e5, 2e5}, {10, 1e5}})
        expectSameAsOpenCv(dx, dy, low, high, "thresholds");
}

TEST(CannyL2, ExtremeDerivativesAsOpenCvTakesThem)
{
    // Derivatives beyond any 3x3 Sobel of 8 bits (up to the documented bound), random signs and directions.
    std::mt19937 rng(11);
    std::uniform_int_distribution<int> u(-27145, 27145);
    cv::Mat dx(64, 64, CV_16SC1), dy(64, 64, CV_16SC1);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
        {
            dx.at<int16_t>(y, x) = int16_t(u(rng) >> (x % 8));
            dy.at<int16_t>(y, x) = int16_t(u(rng) >> (y % 8));
        }
    for (const double high : {100.0, 5000.0, 20000.0}) expectSameAsOpenCv(dx, dy, 0.4 * high, high, "extreme");
}

TEST(CannyL2, RefusesOtherTypesAndSizes)
{
    cv::Mat edges;
    const cv::Mat s16(4, 4, CV_16SC1, cv::Scalar(0)), f32(4, 4, CV_32FC1, cv::Scalar(0)), other(5, 4, CV_16SC1);
    EXPECT_THROW(cannyL2(f32, f32, 1, 2, edges), quasiloc::core::InputError);
    EXPECT_THROW(cannyL2(s16, other, 1, 2, edges), quasiloc::core::InputError);
    EXPECT_THROW(cannyL2(cv::Mat(), cv::Mat(), 1, 2, edges), quasiloc::core::InputError);
}
