// Frontend::extract runs the line branch beside the points when OpenCV has more than one thread: the result must
// be the same as running the extractor, the line detector and the descriptors one after the other, and errors of
// either branch must reach the caller.
#include <gtest/gtest.h>

#include <opencv2/core/utility.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/frontend/frontend.h>

#include "test_options.h"
#include "test_scenes.h"

using namespace quasiloc::frontend;

namespace
{
FrontendOptions optionsFor(const std::string& type)
{
    FrontendOptions o;
    o.features = test::withIni(o.features, "Features", "type = " + type);
    if (type == "xfeat")
        o.features.xfeat_model_path = std::string(QUASILOC_SHARED_DIR) + "/models/xfeat/xfeat_dyn_op11.onnx";
    return o;
}

/** The extraction as three plain calls, in order. */
FrameFeatures sequential(const FrontendOptions& o, const cv::Mat& gray, const cv::Mat& mask)
{
    FrameFeatures f;
    createFeatureExtractor(o.features)->extract(gray, mask, f.points);
    f.lines = LineDetector(o.lines).detect(gray, mask);
    f.line_descriptors = describeLines(gray, f.points.dense, f.lines, o.lines);
    return f;
}

bool sameMat(const cv::Mat& a, const cv::Mat& b)
{
    return a.size() == b.size() && a.type() == b.type() && (a.empty() || cv::norm(a, b, cv::NORM_INF) == 0);
}

void expectSame(const FrameFeatures& a, const FrameFeatures& b)
{
    ASSERT_EQ(a.points.keypoints.size(), b.points.keypoints.size());
    for (size_t k = 0; k < a.points.keypoints.size(); ++k)
    {
        EXPECT_EQ(a.points.keypoints[k].pt, b.points.keypoints[k].pt);
        EXPECT_EQ(a.points.keypoints[k].response, b.points.keypoints[k].response);
    }
    EXPECT_TRUE(sameMat(a.points.descriptors, b.points.descriptors));
    EXPECT_TRUE(sameMat(a.points.dense.data, b.points.dense.data));
    EXPECT_EQ(a.points.dense.cols_cells, b.points.dense.cols_cells);
    ASSERT_EQ(a.lines.size(), b.lines.size());
    for (size_t k = 0; k < a.lines.size(); ++k)
    {
        EXPECT_EQ(a.lines[k].p0, b.lines[k].p0);
        EXPECT_EQ(a.lines[k].p1, b.lines[k].p1);
    }
    EXPECT_TRUE(sameMat(a.line_descriptors, b.line_descriptors));
}

/** Restores OpenCV's thread count when a test ends. */
struct ThreadCount
{
    int saved = cv::getNumThreads();
    ~ThreadCount() { cv::setNumThreads(saved); }
};

class FrontendPerExtractor : public ::testing::TestWithParam<std::string>
{};
}  // namespace

TEST_P(FrontendPerExtractor, ConcurrentExtractionEqualsTheSequentialOne)
{
    const FrontendOptions o = optionsFor(GetParam());
    const cv::Mat img = test::texturedImage(640, 480, 21);
    cv::Mat mask = cv::Mat::zeros(img.size(), CV_8UC1);
    mask(cv::Rect(40, 30, 520, 400)).setTo(255);
    const ThreadCount restore;
    for (const cv::Mat& m : {cv::Mat(), mask})
    {
        const FrameFeatures expected = sequential(o, img, m);
        ASSERT_GT(expected.points.size(), 100u);
        ASSERT_GT(expected.lines.size(), 10u);
        for (int threads : {2, 1})
        {
            cv::setNumThreads(threads);
            Frontend fe(o);
            FrameFeatures f;
            fe.extract(img, m, f);
            expectSame(f, expected);
            EXPECT_GT(f.total_ms, 0);
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Extractors, FrontendPerExtractor, ::testing::Values("orb", "sift", "akaze", "xfeat"));

TEST(Frontend, ErrorsOfEitherBranchReachTheCaller)
{
    const ThreadCount restore;
    for (int threads : {2, 1})
    {
        cv::setNumThreads(threads);
        Frontend fe(FrontendOptions{});
        FrameFeatures f;
        // Both branches reject an empty image; only the point extractor rejects a mask of the wrong size.
        EXPECT_THROW(fe.extract(cv::Mat(), cv::Mat(), f), quasiloc::core::InputError);
        EXPECT_THROW(fe.extract(test::texturedImage(), cv::Mat::zeros(50, 50, CV_8UC1), f), quasiloc::core::InputError);
        // The object is still usable.
        fe.extract(test::texturedImage(), cv::Mat(), f);
        EXPECT_GT(f.points.size(), 100u);
    }
}

TEST(Frontend, OneFrontendForImagesOfDifferentSizes)
{
    // The working images kept between frames (dense map, line gradients) must not leak into the next result.
    const FrontendOptions o = optionsFor("orb");
    Frontend fe(o);
    for (const auto& img : {test::texturedImage(640, 480, 31), test::texturedImage(752, 480, 32),
                            test::texturedImage(320, 240, 33), test::texturedImage(640, 480, 34)})
    {
        FrameFeatures f;
        fe.extract(img, cv::Mat(), f);
        expectSame(f, sequential(o, img, cv::Mat()));
    }
}
