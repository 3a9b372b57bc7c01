#include <gtest/gtest.h>

#include <quasiloc/map/lidar_map.h>
#include <random>

#include "near_points.h"

using namespace quasiloc;

TEST(NearPoints, NearestWithinTheRadiusEqualsABruteForceSearchOfTheWholeMap)
{
    // A wall, a floor and scattered points, and queries near and away from them.
    map::LidarMap m;
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> U(0.f, 1.f);
    for (int i = 0; i < 40000; ++i) m.addPoint(6 * U(rng), 2.f + 0.002f * U(rng), 3 * U(rng), 0.5f);
    for (int i = 0; i < 40000; ++i) m.addPoint(6 * U(rng), 4 * U(rng), 0.003f * U(rng), 0.5f);
    for (int i = 0; i < 2000; ++i) m.addPoint(-20 + 40 * U(rng), -20 + 40 * U(rng), 5 * U(rng), 0.5f);
    const map::VisibilityIndex index(m, {});
    std::vector<Eigen::Vector3f> queries;
    for (int i = 0; i < 500; ++i) queries.emplace_back(-1 + 8 * U(rng), -1 + 6 * U(rng), -0.2f + 3.4f * U(rng));
    for (int i = 0; i < 500; ++i)  // near the surfaces
        queries.push_back(m.point(size_t(80000 * U(rng))) + 0.1f * Eigen::Vector3f(U(rng), U(rng), U(rng)));
    const float radius = 0.1f, reach = 0.25f;
    const reloc::NearPoints near(index, queries, reach, radius);
    EXPECT_LT(near.size(), m.size()) << "only the points near the queries are kept";
    int found = 0;
    for (const auto& q0 : queries)
    {
        // Queries moved by up to reach - radius from where the points were gathered stay exact.
        const Eigen::Vector3f q = q0 + Eigen::Vector3f(0.1f, -0.05f, 0.05f);
        float best = radius * radius;
        bool any = false;
        for (size_t i = 0; i < m.size(); ++i)
            if (const float d = (m.point(i) - q).squaredNorm(); d < best) best = d, any = true;
        Eigen::Vector3f p;
        float d2 = 0;
        ASSERT_EQ(near.nearest(q, radius, p, d2), any);
        if (!any) continue;
        ++found;
        EXPECT_EQ(d2, best);
        EXPECT_EQ((p - q).squaredNorm(), best);
    }
    EXPECT_GT(found, 100);
}
