// LighterGlue through libtorch (compiled only in builds that have it): an XFeat image matched with a
// homography-warped copy of itself; most matches must agree with the homography. Skipped only when a model file
// of ../shared/models is missing.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <quasiloc/frontend/features.h>
#include <quasiloc/frontend/point_matcher.h>
#include <sys/stat.h>

#include "../test_scenes.h"

using namespace quasiloc::frontend;

namespace
{
const std::string kShared = QUASILOC_SHARED_DIR;
const std::string kXFeat = kShared + "/models/xfeat/xfeat_dyn_op11.onnx";
const std::string kLighterGlue = kShared + "/models/lighterglue/lighterglue_L3_ts.pt";

bool fileExists(const std::string& p)
{
    struct stat st;
    return ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}
}  // namespace

TEST(LighterGlue, MatchesAgreeWithAKnownHomography)
{
    ASSERT_TRUE(lighterGlueAvailable()) << "this file is compiled only in builds with libtorch";
    if (!fileExists(kXFeat) || !fileExists(kLighterGlue))
        GTEST_SKIP() << "model file missing: " << kXFeat << " or " << kLighterGlue;

    const cv::Mat img = test::texturedImage();
    // Rotation 8 deg, scale 0.92, shift, mild perspective (as point_matcher_unittest's classical case).
    const double a = 8 * M_PI / 180, s = 0.92;
    const cv::Matx33d H(s * std::cos(a), -s * std::sin(a), 60, s * std::sin(a), s * std::cos(a), -10, 4e-5, -2e-5, 1);
    cv::Mat warped;
    cv::warpPerspective(img, warped, cv::Mat(H), img.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);

    FeatureOptions fo;
    fo.type = FeatureType::XFeat;
    fo.xfeat_model_path = kXFeat;
    fo.max_keypoints = 500;
    auto extractor = createFeatureExtractor(fo);
    Features f0, f1;
    extractor->extract(img, cv::Mat(), f0);
    extractor->extract(warped, cv::Mat(), f1);
    ASSERT_GE(f0.size(), 200u);
    ASSERT_GE(f1.size(), 200u);

    PointMatchingOptions po;
    po.method = MatchingMethod::LighterGlue;
    po.lighterglue_model = kLighterGlue;
    auto matcher = createPointMatcher(po);
    const auto matches = matcher->match(f0, f1);
    int agree = 0;
    for (const auto& m : matches)
    {
        const cv::Point2f p = f0.keypoints[size_t(m.query)].pt;
        const cv::Vec3d h = H * cv::Vec3d(p.x, p.y, 1);
        const cv::Point2f expected(float(h[0] / h[2]), float(h[1] / h[2]));
        // XFeat keypoints are heat-map maxima of the resampled image: a few pixels of localisation error are normal
        // under this warp (mutual NN on the same features: the same error distribution).
        agree += cv::norm(expected - f1.keypoints[size_t(m.train)].pt) <= 5.0;
        EXPECT_GE(m.similarity, -1.f);
    }
    EXPECT_GE(matches.size(), 100u);
    EXPECT_GE(agree, int(0.8 * double(matches.size()))) << agree << " of " << matches.size() << " agree";

    // The free function with the same options gives the same matches (its cached network).
    const auto again = matchPoints(f0, f1, po);
    ASSERT_EQ(again.size(), matches.size());
    for (size_t k = 0; k < matches.size(); ++k) EXPECT_EQ(again[k].train, matches[k].train);

    // A window gates the network's matches: with a 5 px window around the query's own position almost nothing
    // survives (the homography moves every point by tens of pixels).
    po.window_px = 5;
    EXPECT_LT(matchPoints(f0, f1, po).size(), matches.size() / 10);
}
