#include <gtest/gtest.h>

#include <cmath>
#include <quasiloc/eval/error_stats.h>

using quasiloc::eval::computeStats;

TEST(ErrorStats, ThreeValuesByHand)
{
    // errors 0.1, 0.6, 0.2 (unsorted on purpose): mean 0.3, median 0.2, max 0.6,
    // RMSE sqrt((0.01 + 0.36 + 0.04) / 3), population std sqrt((0.04 + 0.09 + 0.01) / 3).
    const auto s = computeStats({0.1, 0.6, 0.2});
    EXPECT_EQ(s.count, 3u);
    EXPECT_NEAR(s.mean, 0.3, 1e-15);
    EXPECT_NEAR(s.median, 0.2, 1e-15);
    EXPECT_NEAR(s.max, 0.6, 1e-15);
    EXPECT_NEAR(s.min, 0.1, 1e-15);
    EXPECT_NEAR(s.rmse, std::sqrt(0.41 / 3), 1e-15);
    EXPECT_NEAR(s.std, std::sqrt(0.14 / 3), 1e-15);
}

TEST(ErrorStats, EvenCountMedianAndEmpty)
{
    const auto s = computeStats({4, 1, 3, 2});
    EXPECT_DOUBLE_EQ(s.median, 2.5);
    EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(30.0 / 4));
    const auto e = computeStats({});
    EXPECT_EQ(e.count, 0u);
    EXPECT_TRUE(std::isnan(e.rmse) && std::isnan(e.mean) && std::isnan(e.median) && std::isnan(e.max));
}
