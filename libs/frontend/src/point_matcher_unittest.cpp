// Point features and matching: an image matched with itself gives identity matches, a known homography is
// recovered, the window gate holds, the keypoint budget spreads. Every classical extractor, and XFeat with
// the model of ../shared/models (the library itself never requires it).
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/frontend/features.h>
#include <quasiloc/frontend/point_matcher.h>

#include "test_options.h"
#include "test_scenes.h"

using namespace quasiloc::frontend;

namespace
{
std::string xfeatModel() { return std::string(QUASILOC_SHARED_DIR) + "/models/xfeat/xfeat_dyn_op11.onnx"; }

FeatureOptions optionsFor(const std::string& type)
{
    FeatureOptions o = test::withIni(FeatureOptions{}, "Features", "type = " + type);
    o.max_keypoints = 600;
    if (type == "xfeat") o.xfeat_model_path = xfeatModel();
    return o;
}

class PerExtractor : public ::testing::TestWithParam<std::string>
{};
}  // namespace

TEST_P(PerExtractor, SelfMatchingGivesIdentity)
{
    const cv::Mat img = test::texturedImage();
    auto ex = createFeatureExtractor(optionsFor(GetParam()));
    Features f;
    ex->extract(img, cv::Mat(), f);
    ASSERT_GE(f.size(), 200u);
    ASSERT_LE(f.size(), 600u);
    ASSERT_EQ(f.descriptors.rows, int(f.size()));
    PointMatchingOptions pm;
    const auto matches = matchPoints(f, f, pm);
    // Keypoints with a twin descriptor (same place, other octave) fail the ratio test; all others match themselves.
    EXPECT_GE(matches.size(), f.size() * 8 / 10);
    for (const auto& m : matches)
    {
        EXPECT_EQ(m.query, m.train);
        EXPECT_NEAR(m.similarity, 1.f, 1e-4);
    }
}

TEST_P(PerExtractor, RecoversAKnownHomography)
{
    const cv::Mat img = test::texturedImage();
    // Rotation 8 deg, scale 0.92, shift, mild perspective.
    const double a = 8 * M_PI / 180, s = 0.92;
    cv::Matx33d H(s * std::cos(a), -s * std::sin(a), 60, s * std::sin(a), s * std::cos(a), -10, 4e-5, -2e-5, 1);
    cv::Mat warped;
    cv::warpPerspective(img, warped, cv::Mat(H), img.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
    auto ex = createFeatureExtractor(optionsFor(GetParam()));
    Features f0, f1;
    ex->extract(img, cv::Mat(), f0);
    ex->extract(warped, cv::Mat(), f1);
    const auto matches = matchPoints(f0, f1, PointMatchingOptions{});
    ASSERT_GE(matches.size(), 30u);
    std::vector<cv::Point2f> p0, p1;
    for (const auto& m : matches) p0.push_back(f0.keypoints[m.query].pt), p1.push_back(f1.keypoints[m.train].pt);
    cv::Mat inliers;
    const cv::Mat Hest = cv::findHomography(p0, p1, cv::RANSAC, 2.0, inliers);
    ASSERT_FALSE(Hest.empty());
    EXPECT_GE(cv::countNonZero(inliers), 30);
    // Transfer error of a grid of image points, true vs estimated homography.
    double worst = 0, sum = 0;
    int n = 0;
    for (int y = 40; y < img.rows; y += 100)
        for (int x = 40; x < img.cols; x += 100, ++n)
        {
            const cv::Vec3d q(x, y, 1), t = H * q, e = cv::Matx33d(Hest) * q;
            const double err = std::hypot(t[0] / t[2] - e[0] / e[2], t[1] / t[2] - e[1] / e[2]);
            worst = std::max(worst, err), sum += err;
        }
    std::printf("%s: %d inliers of %zu matches, transfer error mean %.2f px, worst %.2f px\n", GetParam().c_str(),
                cv::countNonZero(inliers), matches.size(), sum / n, worst);
    // XFeat keypoints come from 8x8 cells of a stride-8 network, not equivariant to sub-cell motion: they
    // repeat to ~1-2 px (classical detectors to a fraction of a pixel).
    EXPECT_LT(worst, GetParam() == "xfeat" ? 5.0 : 2.0) << GetParam();
}

TEST_P(PerExtractor, WindowGateAndMask)
{
    const cv::Mat img = test::texturedImage();
    cv::Mat mask = cv::Mat::zeros(img.size(), CV_8UC1);
    mask(cv::Rect(0, 0, img.cols / 2, img.rows)).setTo(255);
    auto ex = createFeatureExtractor(optionsFor(GetParam()));
    Features f0, f1;
    ex->extract(img, mask, f0);
    for (const auto& k : f0.keypoints) EXPECT_LT(k.pt.x, img.cols / 2 + 0.5f);
    // The same image shifted by 32 px: a 10 px window around the unshifted position finds nothing right,
    // a 10 px window around the predicted position finds the shifted twins (within 2.5 px: ORB's coarse pyramid levels
    // localise to ~2 px).
    cv::Mat shifted;
    cv::warpAffine(img, shifted, cv::Matx23d(1, 0, 32, 0, 1, 0), img.size(), cv::INTER_NEAREST, cv::BORDER_REFLECT);
    ex->extract(shifted, cv::Mat(), f1);
    SearchRegion near_own;
    near_own.radius_px = 10;
    for (const auto& m : matchPoints(f0, f1, PointMatchingOptions{}, &near_own))
        EXPECT_LE(cv::norm(f1.keypoints[m.train].pt - f0.keypoints[m.query].pt), 10.0 + 1e-3);
    SearchRegion predicted;
    predicted.radius_px = 10;
    for (const auto& k : f0.keypoints) predicted.centers.push_back(k.pt + cv::Point2f(32, 0));
    const auto matches = matchPoints(f0, f1, PointMatchingOptions{}, &predicted);
    ASSERT_GE(matches.size(), 50u);
    size_t right = 0;
    for (const auto& m : matches)
        right += cv::norm(f1.keypoints[m.train].pt - (f0.keypoints[m.query].pt + cv::Point2f(32, 0))) < 2.5;
    EXPECT_GE(right, matches.size() * 9 / 10);
}

INSTANTIATE_TEST_SUITE_P(Extractors, PerExtractor, ::testing::Values("orb", "sift", "akaze", "xfeat"));

TEST(Features, SpreadingKeepsTheBudgetAndCoversTheGrid)
{
    std::vector<cv::KeyPoint> kps;
    // 500 strong keypoints crowded in one corner, 100 weak ones spread everywhere.
    for (int i = 0; i < 500; ++i) kps.emplace_back(cv::Point2f(float(i % 25), float(i / 25)), 7.f, -1.f, 100.f + i);
    for (int i = 0; i < 100; ++i)
        kps.emplace_back(cv::Point2f(float(i % 10) * 64 + 30, float(i / 10) * 48 + 20), 7.f, -1.f, 1.f);
    const auto kept = spreadKeypoints(kps, cv::Size(640, 480), 200, 4, 4);
    ASSERT_EQ(kept.size(), 200u);
    std::vector<int> per_cell(16, 0);
    for (const auto& k : kept) ++per_cell[std::min(3, int(k.pt.y / 120)) * 4 + std::min(3, int(k.pt.x / 160))];
    for (int c = 0; c < 16; ++c) EXPECT_GE(per_cell[c], 1) << "cell " << c;
    EXPECT_EQ(kept.front().response, 599.f);  // strongest first
}

TEST(Features, BadInputIsRejected)
{
    EXPECT_THROW(test::withIni(FeatureOptions{}, "Features", "type = surf"), quasiloc::core::InputError);
    FeatureOptions o;
    o.type = FeatureType::XFeat;
    o.xfeat_model_path = "/nonexistent/xfeat.onnx";
    EXPECT_THROW(createFeatureExtractor(o), quasiloc::core::InputError);
    auto ex = createFeatureExtractor(FeatureOptions{});
    Features f;
    EXPECT_THROW(ex->extract(cv::Mat(), cv::Mat(), f), quasiloc::core::InputError);
    EXPECT_THROW(ex->extract(cv::Mat::zeros(100, 100, CV_8UC3), cv::Mat(), f), quasiloc::core::InputError);
    EXPECT_THROW(ex->extract(cv::Mat::zeros(100, 100, CV_8UC1), cv::Mat::zeros(50, 50, CV_8UC1), f),
                 quasiloc::core::InputError);
}

TEST(GuidedCandidates, NeverOutsideTheWindow)
{
    // Guided association (map_refinement.h): every camera keypoint keeps up to k candidates among the quasi-image
    // keypoints within radius_px of its own position. The best descriptor matches are planted OUTSIDE the window
    // (an identical descriptor 30-60 px away), so a gate that leaked would return them first.
    cv::RNG rng(7);
    const int n = 200;
    Features query, train;
    query.descriptors.create(n, 32, CV_8U);
    train.descriptors.create(3 * n, 32, CV_8U);
    rng.fill(query.descriptors, cv::RNG::UNIFORM, 0, 256);
    rng.fill(train.descriptors, cv::RNG::UNIFORM, 0, 256);
    for (int i = 0; i < n; ++i)
    {
        const cv::Point2f p(rng.uniform(50.f, 590.f), rng.uniform(50.f, 430.f));
        query.keypoints.emplace_back(p, 7.f);
        const float a = rng.uniform(0.f, float(2 * M_PI)), r_far = rng.uniform(30.f, 60.f),
                    r_near = rng.uniform(0.f, 12.f);
        train.keypoints.emplace_back(p + r_far * cv::Point2f(std::cos(a), std::sin(a)), 7.f);           // twin, far
        train.keypoints.emplace_back(p + r_near * cv::Point2f(std::sin(a), std::cos(a)), 7.f);          // near
        train.keypoints.emplace_back(p + 0.5f * r_near * cv::Point2f(std::cos(a), -std::sin(a)), 7.f);  // near
        query.descriptors.row(i).copyTo(train.descriptors.row(3 * i));
    }
    SearchRegion region;
    region.radius_px = 15;
    const auto candidates = findCandidates(query, train, 3, 256, region);
    ASSERT_EQ(candidates.size(), size_t(n));
    size_t total = 0;
    for (int i = 0; i < n; ++i)
    {
        EXPECT_LE(candidates[size_t(i)].size(), 3u);
        for (const PointCandidate& c : candidates[size_t(i)])
        {
            ++total;
            EXPECT_LE(cv::norm(train.keypoints[size_t(c.index)].pt - query.keypoints[size_t(i)].pt), 15.0 + 1e-4)
                << "query " << i << " candidate " << c.index;
        }
    }
    EXPECT_GE(total, size_t(n)) << "the near keypoints must still be found";
    // The same with the window centred on a prediction 40 px to the right: only keypoints near the prediction.
    for (const auto& k : query.keypoints) region.centers.push_back(k.pt + cv::Point2f(40, 0));
    const auto shifted = findCandidates(query, train, 3, 256, region);
    for (int i = 0; i < n; ++i)
        for (const PointCandidate& c : shifted[size_t(i)])
            EXPECT_LE(cv::norm(train.keypoints[size_t(c.index)].pt - region.centers[size_t(i)]), 15.0 + 1e-4)
                << "query " << i << " candidate " << c.index << " (shifted window)";
}
