#include <algorithm>
#include <cmath>
#include <quasiloc/quasi/synthetic_scene.h>

namespace quasiloc::quasi
{
namespace
{
/** Small deterministic generator (no dependence on the standard library's distributions). */
struct Lcg
{
    uint64_t s;
    float uniform()  // [-1, 1)
    {
        s = s * 6364136223846793005ull + 1442695040888963407ull;
        return float((s >> 40) & 0xffffff) / float(1 << 23) - 1.0f;
    }
};

struct Box
{
    Eigen::Vector3f centre, size;
};

/** The boxes standing in the room (relative to a room of size 8 x 8 x 3, scaled). */
std::vector<Box> roomBoxes(float size_m, float height_m)
{
    const float k = size_m / 8.0f, h = height_m / 3.0f;
    return {{{1.5f * k, 1.0f * k, 0.4f * h}, {1.2f * k, 0.8f * k, 0.8f * h}},
            {{-2.0f * k, -1.5f * k, 0.6f * h}, {0.6f * k, 1.6f * k, 1.2f * h}},
            {{-1.0f * k, 2.2f * k, 0.9f * h}, {0.5f * k, 0.5f * k, 1.8f * h}},
            {{2.5f * k, -2.5f * k, 0.3f * h}, {1.5f * k, 1.0f * k, 0.6f * h}}};
}

double boxesArea(const std::vector<Box>& boxes)
{
    double a = 0;
    for (const Box& b : boxes) a += 2.0 * (b.size.x() * b.size.y() + b.size.x() * b.size.z() + b.size.y() * b.size.z());
    return a;
}
}  // namespace

ReflectivityPattern checkerPattern(float cell_m)
{
    return [cell_m](float s, float t) {
        const int cs = int(std::floor(s / cell_m)), ct = int(std::floor(t / cell_m));
        const float checker = ((cs + ct) & 1) ? 0.75f : 0.25f;
        const float stripes = 0.1f * std::sin(6.2831853f * (s + 0.5f * t) / (5.3f * cell_m));
        return std::clamp(checker + stripes, 0.0f, 1.0f);
    };
}

ReflectivityPattern constantPattern(float reflectivity)
{
    return [reflectivity](float, float) { return reflectivity; };
}

size_t addPlanarPatch(map::LidarMap& map, const Eigen::Vector3f& origin, const Eigen::Vector3f& axis_u,
                      const Eigen::Vector3f& axis_v, float spacing_m, const ReflectivityPattern& reflectivity,
                      float jitter, uint32_t seed)
{
    const float lu = axis_u.norm(), lv = axis_v.norm();
    if (!(spacing_m > 0) || lu <= 0 || lv <= 0) return 0;
    const int nu = std::max(1, int(std::floor(lu / spacing_m))), nv = std::max(1, int(std::floor(lv / spacing_m)));
    const Eigen::Vector3f eu = axis_u / lu, ev = axis_v / lv;
    Lcg rng{0x9e3779b97f4a7c15ull ^ seed};
    size_t added = 0;
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i)
        {
            // Cell centres, jittered, clamped into the patch.
            const float s = std::clamp((i + 0.5f + jitter * rng.uniform()) * spacing_m, 0.0f, lu);
            const float t = std::clamp((j + 0.5f + jitter * rng.uniform()) * spacing_m, 0.0f, lv);
            const Eigen::Vector3f p = origin + s * eu + t * ev;
            map.addPoint(p.x(), p.y(), p.z(), std::clamp(reflectivity(s, t), 0.0f, 1.0f));
            ++added;
        }
    return added;
}

map::LidarMap makeSyntheticRoom(size_t approx_points, float size_m, float height_m)
{
    const std::vector<Box> boxes = roomBoxes(size_m, height_m);
    const double area = 2.0 * size_m * size_m + 4.0 * size_m * height_m + boxesArea(boxes);
    const float spacing = float(std::sqrt(area / double(std::max<size_t>(approx_points, 1))));
    map::LidarMap map;
    map.reserve(approx_points + approx_points / 10);
    const float a = size_m / 2;
    const auto pattern = checkerPattern(0.4f);
    uint32_t seed = 1;
    auto quad = [&](Eigen::Vector3f o, Eigen::Vector3f u, Eigen::Vector3f v) {
        addPlanarPatch(map, o, u, v, spacing, pattern, 0.3f, seed++);
    };
    quad({-a, -a, 0}, {size_m, 0, 0}, {0, size_m, 0});         // floor
    quad({-a, -a, height_m}, {size_m, 0, 0}, {0, size_m, 0});  // ceiling
    quad({-a, -a, 0}, {size_m, 0, 0}, {0, 0, height_m});       // walls
    quad({-a, a, 0}, {size_m, 0, 0}, {0, 0, height_m});
    quad({-a, -a, 0}, {0, size_m, 0}, {0, 0, height_m});
    quad({a, -a, 0}, {0, size_m, 0}, {0, 0, height_m});
    for (const Box& b : boxes)
    {
        const Eigen::Vector3f lo = b.centre - 0.5f * b.size;
        const Eigen::Vector3f ex(b.size.x(), 0, 0), ey(0, b.size.y(), 0), ez(0, 0, b.size.z());
        quad(lo, ex, ey), quad(lo + ez, ex, ey);
        quad(lo, ex, ez), quad(lo + ey, ex, ez);
        quad(lo, ey, ez), quad(lo + ex, ey, ez);
    }
    return map;
}

}  // namespace quasiloc::quasi
