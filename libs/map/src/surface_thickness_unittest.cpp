#include <gtest/gtest.h>

#include <quasiloc/map/surface_thickness.h>
#include <random>

namespace quasiloc::map
{
namespace
{
/** Two walls meeting at a corner and a floor, 4 x 4 m each, with Gaussian noise across the surfaces. */
LidarMap roomCorner(double noise_m, double spacing_m = 0.02)
{
    LidarMap map;
    std::mt19937 rng(7);
    std::normal_distribution<float> n(0.f, float(noise_m));
    for (double a = 0; a < 4; a += spacing_m)
        for (double b = 0; b < 4; b += spacing_m)
        {
            map.addPoint(float(a), float(b), n(rng), 0.5f);  // floor
            map.addPoint(float(a), n(rng), float(b), 0.5f);  // wall y = 0
            map.addPoint(n(rng), float(a), float(b), 0.5f);  // wall x = 0
        }
    return map;
}
}  // namespace

TEST(SurfaceThickness, RecoversTheNoiseAcrossTheSurfaces)
{
    for (double noise : {0.002, 0.01, 0.02})
    {
        const SurfaceThickness t = measureSurfaceThickness(roomCorner(noise));
        EXPECT_GT(t.surface_patches, 3000u) << noise;
        EXPECT_NEAR(t.median_m, noise, 0.15 * noise + 0.0005) << noise;
    }
}

TEST(SurfaceThickness, APoleIsNoSurface)
{
    LidarMap map;
    std::mt19937 rng(3);
    std::normal_distribution<float> n(0.f, 0.01f);
    for (int i = 0; i < 20000; ++i) map.addPoint(n(rng), n(rng), float(i) * 1e-4f, 0.5f);
    const SurfaceThickness t = measureSurfaceThickness(map);
    EXPECT_EQ(t.surface_patches, 0u);
    EXPECT_EQ(t.median_m, 0.0);
}

TEST(SurfaceThickness, AnEmptyMapHasNoPatches)
{
    const SurfaceThickness t = measureSurfaceThickness(LidarMap());
    EXPECT_EQ(t.sampled_patches, 0u);
}

}  // namespace quasiloc::map
