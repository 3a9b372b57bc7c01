#include <gtest/gtest.h>

#include <quasiloc/dataset/timestamps.h>

using namespace quasiloc::dataset;

TEST(Timestamps, NanosecondsSurviveWithinDoublePrecision)
{
    const std::int64_t t_ns = 1403715273262142976;  // a EuRoC timestamp: 19 digits, more than a double holds
    EXPECT_LE(std::abs(secondsToNs(nsToSeconds(t_ns)) - t_ns), 240);  // one double ulp at 1.4e9 s
    // Naive conversion through double(t_ns) loses up to 128 ns before scaling; ours keeps the ns part.
    EXPECT_NEAR(nsToSeconds(t_ns) - 1403715273.0, 0.262142976, 3e-7);
    EXPECT_EQ(secondsToNs(1.5), 1500000000);
    EXPECT_EQ(secondsToNs(-0.25), -250000000);
}

TEST(Timestamps, MrptTimeAgreesWithClockAndRoundsToTicks)
{
    const std::int64_t t_ns = 1403715273262142976;
    const auto t = mrptTimeFromNs(t_ns);
    EXPECT_EQ(mrptTimeToNs(t), 1403715273262143000);  // nearest 100 ns tick
    EXPECT_NEAR(mrpt::Clock::toDouble(t), nsToSeconds(t_ns), 1e-6);
    EXPECT_NEAR(mrptTimeToSeconds(mrpt::Clock::fromDouble(1403715273.5)), 1403715273.5, 1e-6);
    EXPECT_EQ(mrptTimeToNs(mrptTimeFromNs(0)), 0);
    EXPECT_EQ(mrptTimeToNs(mrptTimeFromNs(149)), 100);
    EXPECT_EQ(mrptTimeToNs(mrptTimeFromNs(150)), 200);
}
