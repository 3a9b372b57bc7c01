// The session's input guard: duplicated, out-of-order and IMU-less frames are rejected with one warning per fault,
// and the IMU samples that only they carried reach the next frame.
#include <gtest/gtest.h>

#include <quasiloc/tracking/input_guard.h>
#include <sstream>

using namespace quasiloc;
using dataset::StereoFrame;

namespace
{
StereoFrame frame(size_t index, double t, std::vector<double> imu_times)
{
    StereoFrame f;
    f.index = index;
    f.timestamp = t;
    for (double s : imu_times) f.imu.push_back({s, {}, {}});
    return f;
}

size_t lines(const std::string& s, const std::string& what)
{
    size_t n = 0;
    for (size_t at = s.find(what); at != std::string::npos; at = s.find(what, at + 1)) ++n;
    return n;
}
}  // namespace

TEST(InputGuard, InOrderFramesPass)
{
    std::ostringstream console;
    tracking::InputGuard g(console);
    for (int k = 0; k < 5; ++k)
    {
        StereoFrame f = frame(size_t(k), 0.05 * k, {0.05 * k - 0.025, 0.05 * k});
        EXPECT_TRUE(g.accept(f));
        EXPECT_FALSE(g.lastWasFaulty(0.15));
    }
    EXPECT_TRUE(console.str().empty());
}

TEST(InputGuard, ADuplicatedTimestampIsRejectedOnceAndTheRunGoesOn)
{
    std::ostringstream console;
    tracking::InputGuard g(console);
    StereoFrame a = frame(0, 1.0, {0.99, 1.0}), dup = frame(1, 1.0, {}), b = frame(2, 1.05, {1.025, 1.05});
    EXPECT_TRUE(g.accept(a));
    EXPECT_FALSE(g.accept(dup));
    EXPECT_TRUE(g.accept(b));
    EXPECT_TRUE(g.lastWasFaulty(0.15)) << "the frame after a rejection is not trusted blindly";
    EXPECT_EQ(lines(console.str(), "input fault: frame 1 at t 1.000000 rejected: duplicated timestamp"), 1u)
        << console.str();
    EXPECT_EQ(g.rejectedFrames(), 1u);
}

TEST(InputGuard, AnOutOfOrderFrameIsRejectedAndItsNewImuSamplesAreKept)
{
    std::ostringstream console;
    tracking::InputGuard g(console);
    StereoFrame a = frame(0, 1.0, {1.0}), later = frame(1, 1.10, {1.05, 1.10}),
                late = frame(2, 1.05, {1.05, 1.12}),  // 1.05 was passed on, 1.12 is new
        next = frame(3, 1.15, {1.15});
    EXPECT_TRUE(g.accept(a));
    EXPECT_TRUE(g.accept(later));
    EXPECT_FALSE(g.accept(late));
    EXPECT_TRUE(g.accept(next));
    ASSERT_EQ(next.imu.size(), 2u);
    EXPECT_DOUBLE_EQ(next.imu[0].t, 1.12);
    EXPECT_EQ(lines(console.str(), "rejected: timestamp earlier than the previous frame's"), 1u) << console.str();
}

TEST(InputGuard, FramesWithoutImuAreRejectedAsOneGap)
{
    std::ostringstream console;
    tracking::InputGuard g(console);
    StereoFrame a = frame(0, 1.0, {1.0});
    EXPECT_TRUE(g.accept(a));
    for (int k = 1; k <= 4; ++k)
    {
        StereoFrame gap = frame(size_t(k), 1.0 + 0.05 * k, {});
        EXPECT_FALSE(g.accept(gap));
    }
    StereoFrame b = frame(5, 1.25, {1.23, 1.25});
    EXPECT_TRUE(g.accept(b));
    EXPECT_NEAR(g.lastImuGapS(), 0.23, 1e-9);
    EXPECT_NEAR(g.lastFrameGapS(), 0.25, 1e-9);
    EXPECT_TRUE(g.lastWasFaulty(0.15));
    EXPECT_EQ(lines(console.str(), "rejected: no IMU sample"), 1u) << console.str();
    EXPECT_EQ(lines(console.str(), "input fault over: 4 frame(s) not tracked"), 1u) << console.str();
}
