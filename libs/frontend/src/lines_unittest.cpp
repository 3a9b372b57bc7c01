// Line detection (LSD, FLD, EDLines), the hybrid descriptor and optimal-transport line matching.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/frontend/line_matcher.h>
#include <quasiloc/frontend/lines.h>

#include "test_options.h"
#include "test_scenes.h"

using namespace quasiloc::frontend;

namespace
{
class PerDetector : public ::testing::TestWithParam<std::string>
{};

LineOptions lineOptions(const std::string& detector)
{
    return test::withIni(LineOptions{}, "Lines", "detector = " + detector);
}
}  // namespace

TEST_P(PerDetector, FindsTheEdgesOfASquare)
{
    cv::Mat img(480, 640, CV_8UC1, cv::Scalar(200));
    cv::rectangle(img, cv::Rect(200, 150, 200, 160), cv::Scalar(40), cv::FILLED);
    cv::GaussianBlur(img, img, cv::Size(3, 3), 0.8);
    LineDetector det(lineOptions(GetParam()));
    const auto lines = det.detect(img);
    ASSERT_GE(lines.size(), 4u);
    // The top edge y = 149.5 from x = 200 to 400: some segment lies on it, long.
    bool top = false;
    for (const auto& l : lines)
    {
        EXPECT_GE(l.length(), 25.f);
        if (std::abs(l.p0.y() - 149.5f) < 1.5f && std::abs(l.p1.y() - 149.5f) < 1.5f && l.length() > 150) top = true;
    }
    EXPECT_TRUE(top) << GetParam();
}

TEST_P(PerDetector, SelfMatchingGivesIdentity)
{
    const cv::Mat img = test::texturedImage();
    const LineOptions lo = lineOptions(GetParam());
    LineDetector det(lo);
    auto lines = det.detect(img);
    ASSERT_GE(lines.size(), 20u);
    const DenseMap dense = computeGradientDenseMap(img);
    const cv::Mat desc = describeLines(img, dense, lines, lo);
    ASSERT_EQ(desc.rows, int(lines.size()));
    for (int i = 0; i < desc.rows; ++i) EXPECT_NEAR(cv::norm(desc.row(i)), 1.0, 1e-5);
    const LineMatchResult r = matchLines(desc, lines, desc, lines, LineMatchingOptions{}, true);
    EXPECT_GE(r.matches.size(), lines.size() * 8 / 10);
    for (const auto& m : r.matches) EXPECT_EQ(m.query, m.train);
}

INSTANTIATE_TEST_SUITE_P(Detectors, PerDetector, ::testing::Values("lsd", "fld", "edlines"));

TEST(LineDescriptor, IndependentOfEndpointOrder)
{
    const cv::Mat img = test::texturedImage();
    const LineOptions lo;
    LineDetector det(lo);
    auto lines = det.detect(img);
    ASSERT_GE(lines.size(), 5u);
    auto reversed = lines;
    for (auto& l : reversed) std::swap(l.p0, l.p1);
    const DenseMap dense = computeGradientDenseMap(img);
    const cv::Mat a = describeLines(img, dense, lines, lo), b = describeLines(img, dense, reversed, lo);
    EXPECT_LT(cv::norm(a - b, cv::NORM_INF), 1e-5);
    for (size_t i = 0; i < lines.size(); ++i) EXPECT_LT((lines[i].p0 - reversed[i].p0).norm(), 1e-5f);
}

TEST(LineMatching, TranslatedImageAndGate)
{
    const cv::Mat img = test::texturedImage();
    cv::Mat shifted;
    cv::warpAffine(img, shifted, cv::Matx23d(1, 0, 12, 0, 1, 5), img.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
    const LineOptions lo;
    LineDetector det(lo);
    auto l0 = det.detect(img), l1 = det.detect(shifted);
    const cv::Mat d0 = describeLines(img, computeGradientDenseMap(img), l0, lo);
    const cv::Mat d1 = describeLines(shifted, computeGradientDenseMap(shifted), l1, lo);
    LineMatchingOptions mo;
    mo.gate_max_distance_px = 20;
    const LineMatchResult r = matchLines(d0, l0, d1, l1, mo, true);
    ASSERT_GE(r.matches.size(), 15u);
    size_t right = 0;
    for (const auto& m : r.matches)
    {
        LineSegment moved = l0[m.query];
        moved.p0 += Eigen::Vector2f(12, 5), moved.p1 += Eigen::Vector2f(12, 5);
        right += l1[m.train].distanceToLine(moved.midpoint()) < 1.5f &&
                 std::abs(moved.direction().dot(l1[m.train].direction())) > 0.99f;
        EXPECT_TRUE(lineGate(l0[m.query], l1[m.train], mo));
    }
    EXPECT_GE(right, r.matches.size() * 9 / 10);
    // A gate narrower than the shift removes every pair.
    mo.gate_max_distance_px = 2;
    LineSegment far = l0[0];
    far.p0 += Eigen::Vector2f(0, 50), far.p1 += Eigen::Vector2f(0, 50);
    EXPECT_FALSE(lineGate(l0[0], far, mo));
}

TEST(Lines, OptionsAreChecked)
{
    EXPECT_THROW(test::withIni(LineOptions{}, "Lines", "detector = hough"), quasiloc::core::InputError);
    LineOptions o;
    o.line_branch_weight = 0, o.point_branch_weight = 0;
    EXPECT_THROW(o.check("test"), quasiloc::core::InputError);
    EXPECT_THROW(LineDetector{o}, quasiloc::core::InputError);
    EXPECT_THROW(test::withIni(LineMatchingOptions{}, "LineMatching", "epsilon = 0"), quasiloc::core::InputError);
}
