// The changes to a state prior before a frame: a zero-velocity update and a widened velocity.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <quasiloc/tracking/zero_velocity_update.h>

namespace quasiloc::tracking
{
namespace
{
/** A prior with every block correlated: the covariance of a random 15x15 square root. */
estimation::StatePrior correlatedPrior(estimation::Matrix15d& covariance)
{
    std::srand(3);
    const estimation::Matrix15d a = estimation::Matrix15d::Random() * 0.3;
    covariance = a * a.transpose() + 0.01 * estimation::Matrix15d::Identity();
    estimation::StatePrior prior;
    prior.mean.v_map = Eigen::Vector3d(0.4, -0.2, 0.05);
    prior.information = covariance.inverse();
    return prior;
}
}  // namespace

TEST(ZeroVelocityUpdate, WideningAddsVarianceToTheVelocityAlone)
{
    estimation::Matrix15d covariance;
    estimation::StatePrior prior = correlatedPrior(covariance);
    widenVelocity(prior, 0.25);
    const estimation::Matrix15d widened = prior.information.inverse();
    estimation::Matrix15d expected = covariance;
    expected.block<3, 3>(6, 6) += 0.25 * Eigen::Matrix3d::Identity();
    EXPECT_LT((widened - expected).cwiseAbs().maxCoeff(), 1e-9) << widened - expected;
    EXPECT_DOUBLE_EQ(prior.mean.v_map.x(), 0.4);  // the mean stays
}

TEST(ZeroVelocityUpdate, NoVarianceLeavesThePriorAsItWas)
{
    estimation::Matrix15d covariance;
    estimation::StatePrior prior = correlatedPrior(covariance);
    const estimation::Matrix15d before = prior.information;
    widenVelocity(prior, 0);
    EXPECT_EQ(prior.information, before);
}

TEST(ZeroVelocityUpdate, AStandingPlatformHasZeroVelocityIndependentOfTheRest)
{
    estimation::Matrix15d covariance;
    estimation::StatePrior prior = correlatedPrior(covariance);
    const estimation::Matrix15d before = prior.information;
    estimation::FrameState state = prior.mean;
    applyZeroVelocity(state, prior, 0.01);
    EXPECT_EQ(state.v_map, Eigen::Vector3d::Zero());
    EXPECT_EQ(prior.mean.v_map, Eigen::Vector3d::Zero());
    const estimation::Matrix15d cov = prior.information.inverse();
    EXPECT_NEAR(cov(7, 7), 1e-4, 1e-12);
    const double to_pose = cov.block<3, 6>(6, 0).cwiseAbs().maxCoeff();
    const double to_biases = cov.block<3, 6>(6, 9).cwiseAbs().maxCoeff();
    EXPECT_LT(to_pose, 1e-12);
    EXPECT_LT(to_biases, 1e-12);
    // The other blocks' information is what it was.
    const estimation::Matrix6d pose_after = prior.information.topLeftCorner<6, 6>();
    const estimation::Matrix6d biases_after = prior.information.bottomRightCorner<6, 6>();
    const estimation::Matrix6d pose_before = before.topLeftCorner<6, 6>();
    const estimation::Matrix6d biases_before = before.bottomRightCorner<6, 6>();
    EXPECT_EQ(pose_after, pose_before);
    EXPECT_EQ(biases_after, biases_before);
}

}  // namespace quasiloc::tracking

namespace quasiloc::tracking
{
TEST(ZeroVelocityUpdate, TheImageMotionIsTheMedianOverTheMatches)
{
    std::vector<cv::KeyPoint> previous, current;
    std::vector<frontend::PointMatch> matches;
    for (int i = 0; i < 11; ++i)
    {
        previous.emplace_back(cv::Point2f(10.f * float(i), 5.f), 1.f);
        // Nine points still (0.2 px of noise), two moving far: the median is a still one.
        current.emplace_back(cv::Point2f(10.f * float(i) + (i < 9 ? 0.2f : 30.f), 5.f), 1.f);
        frontend::PointMatch m;
        m.query = i;
        m.train = i;
        matches.push_back(m);
    }
    EXPECT_NEAR(medianImageMotionPx(previous, current, matches, 10), 0.2, 1e-5);
    EXPECT_TRUE(std::isnan(medianImageMotionPx(previous, current, matches, 12)));  // too few matches
    for (size_t i = 0; i < 6; ++i) current[i].pt.x += 3.f;                         // most points move: a run
    EXPECT_NEAR(medianImageMotionPx(previous, current, matches, 10), 3.2, 1e-5);
}
}  // namespace quasiloc::tracking

namespace quasiloc::tracking
{
TEST(ZeroVelocityUpdate, KeypointTracksSeeASlowRunThatFramesToFramesHide)
{
    // 20 keypoints, matched one to one in every frame. Each frame moves them by 0.4 px: below a pixel frame to
    // frame, 4 px over the 10 frames the tracks must span.
    const auto frame = [](float shift) {
        std::vector<cv::KeyPoint> k;
        for (int i = 0; i < 20; ++i) k.emplace_back(cv::Point2f(20.f * float(i) + shift, 50.f), 1.f);
        return k;
    };
    std::vector<frontend::PointMatch> matches;
    for (int i = 0; i < 20; ++i)
    {
        frontend::PointMatch m;
        m.query = m.train = i;
        matches.push_back(m);
    }
    std::vector<std::vector<cv::KeyPoint>> frames;
    for (int f = 0; f <= 12; ++f) frames.push_back(frame(0.4f * float(f)));
    KeypointTracks tracks;
    double motion = NAN;
    for (int f = 1; f <= 12; ++f)
    {
        motion = tracks.add(&frames[size_t(f - 1)], frames[size_t(f - 1)], &frames[size_t(f)], frames[size_t(f)],
                            matches, 10, 10);
        if (f < 10) EXPECT_TRUE(std::isnan(motion)) << "frame " << f;  // tracks too short yet
    }
    EXPECT_NEAR(motion, 0.4 * 12, 1e-4);  // followed from the first frame
    EXPECT_NEAR(medianImageMotionPx(frames[11], frames[12], matches, 10), 0.4, 1e-4);
    // A frame matched to another than the last one added: the tracks start again.
    EXPECT_TRUE(std::isnan(tracks.add(&frames[0], frames[0], &frames[1], frames[1], matches, 10, 10)));
}
}  // namespace quasiloc::tracking
