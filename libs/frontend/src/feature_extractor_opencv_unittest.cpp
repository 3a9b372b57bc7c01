// The ORB extractor describes all candidates in one detectAndCompute pass and keeps the spread rows: keypoints and
// descriptors must be exactly those of detect, spread, then compute on the kept keypoints.
#include <gtest/gtest.h>

#include <opencv2/features2d.hpp>
#include <quasiloc/frontend/features.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <quasiloc/quasi/synthetic_scene.h>

#include "test_scenes.h"

using namespace quasiloc;
using namespace quasiloc::frontend;

TEST(OrbExtractor, OnePassEqualsDetectSpreadCompute)
{
    FeatureOptions o;  // orb, the defaults
    o.dense_map = false;
    const int n = int(o.max_keypoints * o.detect_factor);
    // The detector of feature_extractor_opencv.cpp, for the two-pass reference.
    auto orb = cv::ORB::create(n, 1.2f, o.orb_levels, 19, 0, 2, cv::ORB::HARRIS_SCORE, 31, o.orb_fast_threshold);

    quasi::QuasiRenderer r(quasi::makeSyntheticRoom(300'000), quasi::QuasiOptions{});
    quasi::QuasiImage q;
    r.render(test::cameraPose(-0.5, 0.4, 1.2, 2.0), test::testCamera(), q);
    cv::Mat box = cv::Mat::zeros(480, 640, CV_8UC1);
    box(cv::Rect(60, 40, 500, 380)).setTo(255);
    const std::vector<std::pair<cv::Mat, cv::Mat>> inputs{{test::texturedImage(640, 480, 41), cv::Mat()},
                                                          {test::texturedImage(640, 480, 42), box},
                                                          {q.gray, q.valid},
                                                          {test::texturedImage(752, 480, 43), cv::Mat()}};
    auto ex = createFeatureExtractor(o);
    for (const auto& [img, mask] : inputs)
    {
        std::vector<cv::KeyPoint> kps;
        // Masked inputs (quasi-images) have their own FAST threshold ([Features] orb_fast_threshold_masked).
        orb->setFastThreshold(mask.empty() ? o.orb_fast_threshold : o.orb_fast_threshold_masked);
        orb->detect(img, kps, mask);
        std::vector<cv::KeyPoint> kept = spreadKeypoints(kps, img.size(), o.max_keypoints, o.grid_cols, o.grid_rows);
        cv::Mat desc;
        orb->compute(img, kept, desc);
        ASSERT_GT(kept.size(), 200u);

        Features f;
        ex->extract(img, mask, f);
        ASSERT_EQ(f.keypoints.size(), kept.size());
        for (size_t k = 0; k < kept.size(); ++k)
        {
            EXPECT_EQ(f.keypoints[k].pt, kept[k].pt);
            EXPECT_EQ(f.keypoints[k].response, kept[k].response);
            EXPECT_EQ(f.keypoints[k].angle, kept[k].angle);
            EXPECT_EQ(f.keypoints[k].octave, kept[k].octave);
        }
        ASSERT_EQ(f.descriptors.size(), desc.size());
        ASSERT_EQ(f.descriptors.type(), desc.type());
        EXPECT_EQ(cv::norm(f.descriptors, desc, cv::NORM_HAMMING), 0.0);
    }
}

TEST(OrbExtractor, SpreadIndicesSelectTheSpreadKeypoints)
{
    std::vector<cv::KeyPoint> kps;
    cv::RNG rng(5);
    for (int i = 0; i < 800; ++i)
        kps.emplace_back(cv::Point2f(rng.uniform(0.f, 640.f), rng.uniform(0.f, 480.f)), 7.f, -1.f,
                         float(rng.uniform(0, 50)));  // many equal responses: the order must be stable
    for (int budget : {0, 100, 799, 800, 1000})
    {
        const auto idx = spreadKeypointIndices(kps, cv::Size(640, 480), budget, 8, 6);
        const auto sel = spreadKeypoints(kps, cv::Size(640, 480), budget, 8, 6);
        ASSERT_EQ(idx.size(), sel.size());
        for (size_t k = 0; k < idx.size(); ++k)
        {
            EXPECT_EQ(kps[size_t(idx[k])].pt, sel[k].pt);
            EXPECT_EQ(kps[size_t(idx[k])].response, sel[k].response);
        }
    }
}
