// Horizontal range profiles of map places and stereo queries (place_descriptor.h).
#include <quasiloc/reloc/place_descriptor.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace quasiloc::reloc
{
namespace
{
/** Distance along the ray from `origin` in the horizontal direction `dir` to the first point of the map within
 *  hit_m, by sphere tracing on the field (a step of the distance to the nearest point cannot pass a point);
 *  max_range_m when there is none. */
float firstHit(const map::DistanceField& field, const Eigen::Vector3f& origin, const Eigen::Vector3f& dir,
               const PlaceDescriptorOptions& o)
{
    const float max_range = float(o.max_range_m), hit = float(o.hit_m);
    const float min_step = 0.5f * field.voxelSize();
    float t = 0;
    while (t < max_range)
    {
        const float d = field.distance(origin + t * dir);
        if (d < hit) return t;
        t += std::max(d - 0.5f * hit, min_step);
    }
    return max_range;
}
}  // namespace

std::vector<float> placeProfile(const map::DistanceField& field, const Eigen::Vector3f& p_world,
                                const PlaceDescriptorOptions& o)
{
    std::vector<float> profile(o.cells(), float(o.max_range_m));
    for (size_t b = 0; b < o.band_centres_m.size(); ++b)
        for (int k = 0; k < o.sectors; ++k)
        {
            const double a = 2 * M_PI * (k + 0.5) / o.sectors;  // the sector's middle
            const Eigen::Vector3f dir(float(std::cos(a)), float(std::sin(a)), 0.f);
            float& v = profile[b * size_t(o.sectors) + size_t(k)];
            for (double dz : o.band_offsets_m)
            {
                const Eigen::Vector3f origin = p_world + Eigen::Vector3f(0, 0, float(o.band_centres_m[b] + dz));
                v = std::min(v, firstHit(field, origin, dir, o));
            }
        }
    return profile;
}

std::vector<float> queryProfile(const std::vector<Eigen::Vector3f>& points_cam, const Eigen::Matrix3f& R_level,
                                const PlaceDescriptorOptions& o)
{
    std::vector<float> profile(o.cells(), std::numeric_limits<float>::quiet_NaN());
    const float band = float(o.band_half_m), max_range = float(o.max_range_m);
    for (const auto& p : points_cam)
    {
        const Eigen::Vector3f q = R_level * p;
        size_t b = 0;
        while (b < o.band_centres_m.size() && std::abs(q.z() - float(o.band_centres_m[b])) > band) ++b;
        if (b == o.band_centres_m.size()) continue;
        const float r = std::hypot(q.x(), q.y());
        if (r >= max_range) continue;
        double a = std::atan2(double(q.y()), double(q.x()));
        if (a < 0) a += 2 * M_PI;
        const int k = std::min(o.sectors - 1, int(a / (2 * M_PI) * o.sectors));
        float& v = profile[b * size_t(o.sectors) + size_t(k)];
        if (std::isnan(v) || r < v) v = r;
    }
    return profile;
}

std::vector<int> coveredSectors(const std::vector<float>& query)
{
    std::vector<int> covered;
    for (size_t k = 0; k < query.size(); ++k)
        if (!std::isnan(query[k])) covered.push_back(int(k));
    return covered;
}

float profileCost(const std::vector<float>& query, const std::vector<int>& covered, const float* place, int shift,
                  int sectors, float truncation_m)
{
    if (covered.empty()) return std::numeric_limits<float>::infinity();
    const float t2 = truncation_m * truncation_m;
    float sum = 0;
    for (int c : covered)
    {
        const int band_start = c - c % sectors;
        const float d = query[size_t(c)] - place[band_start + (c - band_start + shift) % sectors];
        sum += std::min(d * d, t2);
    }
    return sum / float(covered.size());
}

}  // namespace quasiloc::reloc
