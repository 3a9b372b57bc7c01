// The matcher choice in [PointMatching], in every build: what LighterGlue does around its network (mutual best
// assignments, keypoint normalisation, the region gate) and the errors that name the key, whether or not this
// build has libtorch. The network itself is tested in lighterglue/lighterglue_unittest.cpp (libtorch builds only).
#include <gtest/gtest.h>

#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/frontend/frontend.h>
#include <quasiloc/frontend/point_matcher.h>

#include "lighterglue_matcher.h"
#include "test_options.h"

using namespace quasiloc::frontend;

namespace
{
std::string lighterGlueModel() { return std::string(QUASILOC_SHARED_DIR) + "/models/lighterglue/lighterglue_L3_ts.pt"; }

/** The InputError message of f(), "" if it does not throw one. */
template <class F>
std::string inputError(F f)
{
    try
    {
        f();
    }
    catch (const quasiloc::core::InputError& e)
    {
        return e.what();
    }
    return "";
}
}  // namespace

TEST(PointMatcherMethod, MutualBestAssignmentsKeepMutualPairsAboveTheThreshold)
{
    // 3 x 3 inner block + dustbins (log probabilities).
    cv::Mat s(4, 4, CV_32F, cv::Scalar(std::log(1e-3f)));
    s.at<float>(0, 1) = std::log(0.9f);   // 0 <-> 1, mutual
    s.at<float>(1, 1) = std::log(0.5f);   // 1 -> 1, but 1's best row is 0
    s.at<float>(2, 2) = std::log(0.05f);  // mutual but below 0.1
    const auto m = detail::mutualBestAssignments(s, 0.1);
    ASSERT_EQ(m.size(), 1u);
    EXPECT_EQ(m[0], std::make_pair(0, 1));
    EXPECT_EQ(detail::mutualBestAssignments(s, 0.01).size(), 2u);
}

TEST(PointMatcherMethod, KeypointsAreNormalisedByTheLongerSide)
{
    Features f;
    f.image_size = cv::Size(752, 480);
    f.keypoints = {cv::KeyPoint(376, 240, 8), cv::KeyPoint(752, 0, 8)};
    const cv::Mat n = detail::normalisedKeypoints(f);
    EXPECT_FLOAT_EQ(n.at<float>(0, 0), 0.f);
    EXPECT_FLOAT_EQ(n.at<float>(0, 1), 0.f);
    EXPECT_FLOAT_EQ(n.at<float>(1, 0), 1.f);
    EXPECT_FLOAT_EQ(n.at<float>(1, 1), -240.f / 376.f);
}

TEST(PointMatcherMethod, RegionGateFollowsFindCandidatesPrecedence)
{
    Features q, t;
    q.keypoints = {cv::KeyPoint(100, 100, 8)};
    t.keypoints = {cv::KeyPoint(105, 100, 8), cv::KeyPoint(300, 100, 8)};
    SearchRegion window;
    window.radius_px = 10;
    EXPECT_TRUE(detail::regionAllows(window, q, t, 0, 0));
    EXPECT_FALSE(detail::regionAllows(window, q, t, 0, 1));
    window.centers = {cv::Point2f(300, 101)};
    EXPECT_FALSE(detail::regionAllows(window, q, t, 0, 0));
    EXPECT_TRUE(detail::regionAllows(window, q, t, 0, 1));
    SearchRegion subset;
    subset.train_subsets = {{1}};
    EXPECT_FALSE(detail::regionAllows(subset, q, t, 0, 0));
    EXPECT_TRUE(detail::regionAllows(subset, q, t, 0, 1));
    subset.accept = [](int, int) { return false; };
    EXPECT_FALSE(detail::regionAllows(subset, q, t, 0, 1));
}

TEST(PointMatcherMethod, UnknownMethodNamesTheKey)
{
    const std::string e =
        inputError([] { test::withIni(PointMatchingOptions{}, "PointMatching", "method = superglue"); });
    EXPECT_NE(e.find("[PointMatching] method"), std::string::npos) << e;
}

TEST(PointMatcherMethod, LighterGlueErrorsNameTheKey)
{
    PointMatchingOptions o;
    o.method = MatchingMethod::LighterGlue;
    o.lighterglue_model = lighterGlueModel();
    if (!lighterGlueAvailable())
    {
        // A build without libtorch: the method key itself is the error, whatever the model.
        const std::string e = inputError([&] { o.check("test.ini"); });
        EXPECT_NE(e.find("[PointMatching] method"), std::string::npos) << e;
        EXPECT_NE(e.find("libtorch"), std::string::npos) << e;
        EXPECT_NE(inputError([&] { createPointMatcher(o); }), "");
        Features f;
        EXPECT_NE(inputError([&] { matchPoints(f, f, o); }), "");
        return;
    }
    o.lighterglue_model = "/nonexistent/lighterglue.pt";
    EXPECT_NE(inputError([&] { o.check("test.ini"); }).find("[PointMatching] lighterglue_model"), std::string::npos);
    o.lighterglue_model = "";
    EXPECT_NE(inputError([&] { o.check("test.ini"); }).find("[PointMatching] lighterglue_model"), std::string::npos);
}

TEST(PointMatcherMethod, LighterGlueNeedsXFeatFeatures)
{
    FrontendOptions o;
    o.point_matching.method = MatchingMethod::LighterGlue;
    o.point_matching.lighterglue_model = lighterGlueModel();
    o.features.type = FeatureType::Orb;
    // Without libtorch the method is refused first; with it, ORB is: either way the error names the method key.
    EXPECT_NE(inputError([&] { o.check("test.ini"); }).find("[PointMatching] method"), std::string::npos);
}

TEST(PointMatcherMethod, DefaultMatcherIsMutualNearestNeighbour)
{
    Features f;
    f.keypoints = {cv::KeyPoint(10, 10, 8), cv::KeyPoint(50, 10, 8)};
    f.descriptors = (cv::Mat_<float>(2, 2) << 1, 0, 0, 1);
    const auto matcher = createPointMatcher(PointMatchingOptions{});
    const auto m = matcher->match(f, f);
    ASSERT_EQ(m.size(), 2u);
    EXPECT_EQ(m[0].train, 0);
    EXPECT_EQ(m[1].train, 1);
}
