#include <gtest/gtest.h>

#include <quasiloc/dataset/stereo_pairing.h>

using quasiloc::dataset::StereoPairer;

namespace
{
constexpr std::int64_t kMs = 1000000;
}

TEST(StereoPairing, RightImagesThreeMillisecondsLatePairWithinAFiveMillisecondTolerance)
{
    StereoPairer p(5 * kMs);
    for (std::size_t i = 0; i < 10; ++i)
    {
        p.addLeft(i * 50 * kMs, i);
        p.addRight(i * 50 * kMs + 3 * kMs, 100 + i);
    }
    p.finish();
    const auto pairs = p.takePairs();
    ASSERT_EQ(pairs.size(), 10u);
    EXPECT_EQ(pairs[4].left_id, 4u);
    EXPECT_EQ(pairs[4].right_id, 104u);
    EXPECT_EQ(pairs[4].right_ns - pairs[4].left_ns, 3 * kMs);
    EXPECT_EQ(p.numUnpairedLeft() + p.numUnpairedRight(), 0u);
}

TEST(StereoPairing, ThreeMillisecondsLateIsUnpairedWithATwoMillisecondTolerance)
{
    StereoPairer p(2 * kMs);
    for (std::size_t i = 0; i < 10; ++i)
    {
        p.addLeft(i * 50 * kMs, i);
        p.addRight(i * 50 * kMs + 3 * kMs, 100 + i);
    }
    p.finish();
    EXPECT_EQ(p.takePairs().size(), 0u);
    EXPECT_EQ(p.numUnpairedLeft(), 10u);
    EXPECT_EQ(p.numUnpairedRight(), 10u);
    EXPECT_EQ(p.takeUnpaired().size(), 20u);
}

TEST(StereoPairing, AMissingRightImageLeavesOneLeftUnpairedAndTheRestPaired)
{
    StereoPairer p(1 * kMs);
    for (std::size_t i = 0; i < 10; ++i)
    {
        p.addLeft(i * 50 * kMs, i);
        if (i != 3) p.addRight(i * 50 * kMs, 100 + i);
    }
    p.finish();
    EXPECT_EQ(p.takePairs().size(), 9u);
    const auto unpaired = p.takeUnpaired();
    ASSERT_EQ(unpaired.size(), 1u);
    EXPECT_TRUE(unpaired[0].left);
    EXPECT_EQ(unpaired[0].id, 3u);
}

TEST(StereoPairing, TheLeftSideArrivingInBurstsStillPairs)
{
    // All left images first (one topic recorded ahead of the other), then all right ones.
    StereoPairer p(0, 100);
    for (std::size_t i = 0; i < 20; ++i) p.addLeft(i * kMs, i);
    for (std::size_t i = 0; i < 20; ++i) p.addRight(i * kMs, 100 + i);
    EXPECT_EQ(p.takePairs().size(), 20u);
}

TEST(StereoPairing, ATimeGoingBackIsUnpairedAndFlagged)
{
    StereoPairer p(0);
    p.addLeft(10, 0);
    p.addLeft(5, 1);
    const auto unpaired = p.takeUnpaired();
    ASSERT_EQ(unpaired.size(), 1u);
    EXPECT_TRUE(unpaired[0].out_of_order);
    EXPECT_EQ(unpaired[0].id, 1u);
}

TEST(StereoPairing, ASilentSideBoundsWhatWaits)
{
    StereoPairer p(0, 8);
    for (std::size_t i = 0; i < 100; ++i) p.addLeft(i, i);
    EXPECT_EQ(p.numUnpairedLeft(), 92u);
}
