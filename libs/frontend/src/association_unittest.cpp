// Association distributions: scores sum to 1, the nominal candidate stays first, K and the gap hold.
#include <gtest/gtest.h>

#include <quasiloc/core/error.h>
#include <quasiloc/frontend/association.h>

#include "test_options.h"

using namespace quasiloc::frontend;

TEST(Association, ScoresSumToOneAndFollowTheSimilarity)
{
    AssociationOptions o;
    o.max_candidates = 4;
    o.max_similarity_gap = 0.5;
    o.temperature = 0.05;
    const auto d = associationDistribution({{7, 0.9f, 0}, {3, 0.6f, 0}, {5, 0.8f, 0}, {1, 0.85f, 0}, {2, 0.2f, 0}}, o);
    ASSERT_EQ(d.size(), 4u);
    EXPECT_EQ(d[0].index, 7);
    EXPECT_EQ(d[1].index, 1);
    EXPECT_EQ(d[2].index, 5);
    EXPECT_EQ(d[3].index, 3);
    double sum = 0;
    for (const auto& c : d) sum += c.probability;
    EXPECT_NEAR(sum, 1.0, 1e-6);
    for (size_t k = 1; k < d.size(); ++k) EXPECT_LT(d[k].probability, d[k - 1].probability);
    // softmax: p_0 / p_1 = exp((0.9 - 0.85) / 0.05) = e
    EXPECT_NEAR(d[0].probability / d[1].probability, std::exp(1.0), 1e-4);
}

TEST(Association, GapAndSingleCandidate)
{
    AssociationOptions o;
    o.max_similarity_gap = 0.1;
    const auto d = associationDistribution({{0, 0.9f, 0}, {1, 0.75f, 0}}, o);
    ASSERT_EQ(d.size(), 1u);
    EXPECT_FLOAT_EQ(d[0].probability, 1.f);
    EXPECT_TRUE(associationDistribution({}, o).empty());
}

TEST(Association, PointAssociationsKeepTheNominalMatchFirst)
{
    AssociationOptions o;
    o.max_candidates = 3;
    std::vector<std::vector<PointCandidate>> cands(2);
    cands[0] = {{4, 0.1f, 0.95f}, {9, 0.2f, 0.9f}, {2, 0.3f, 0.85f}, {8, 0.4f, 0.8f}};
    cands[1] = {{6, 0.1f, 0.97f}};
    const auto a = pointAssociations({{0, 4, 0.1f, 0.95f}, {1, 6, 0.1f, 0.97f}}, cands, o);
    ASSERT_EQ(a.size(), 2u);
    ASSERT_EQ(a[0].candidates.size(), 3u);
    EXPECT_EQ(a[0].candidates[0].index, 4);
    for (const auto& as : a)
    {
        double sum = 0;
        for (const auto& c : as.candidates) sum += c.probability;
        EXPECT_NEAR(sum, 1.0, 1e-6);
    }
    EXPECT_FLOAT_EQ(a[1].candidates[0].probability, 1.f);
}

TEST(Association, OptionsAreChecked)
{
    EXPECT_THROW(test::withIni(AssociationOptions{}, "Association", "temperature = 0"), quasiloc::core::InputError);
    EXPECT_THROW(test::withIni(AssociationOptions{}, "Association", "max_candidates = 0"), quasiloc::core::InputError);
}
