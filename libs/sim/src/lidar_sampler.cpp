#include <algorithm>
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/sim/lidar_sampler.h>
#include <quasiloc/sim/rasterizer.h>
#include <random>
#include <thread>

namespace quasiloc::sim
{
namespace
{
/** A point sampled on a triangle, before noise and reflectivity. */
struct SurfaceSample
{
    Eigen::Vector3f p;
    uint32_t tri;
    float b1, b2;
    int16_t station = -1;  ///< nearest station that sees it
    float range = 0;
};

std::vector<SurfaceSample> sampleSurfaces(const Mesh& mesh, double density, uint64_t seed)
{
    std::vector<SurfaceSample> out;
    out.reserve(static_cast<size_t>(mesh.area() * density * 1.01) + 16);
    std::uniform_real_distribution<float> u01(0.f, 1.f);
    for (uint32_t t = 0; t < mesh.triangles.size(); ++t)
    {
        std::mt19937 rng(static_cast<uint32_t>(seed * 2654435761u) ^ (t * 2246822519u + 374761393u));
        const double expected = mesh.triangleArea(t) * density;
        const auto n = static_cast<size_t>(expected) + (u01(rng) < expected - std::floor(expected) ? 1 : 0);
        const Triangle& tri = mesh.triangles[t];
        const Eigen::Vector3f a = mesh.vertices[tri.v[0]].p, b = mesh.vertices[tri.v[1]].p,
                              c = mesh.vertices[tri.v[2]].p;
        for (size_t i = 0; i < n; ++i)
        {
            float r1 = u01(rng), r2 = u01(rng);
            if (r1 + r2 > 1)
            {
                r1 = 1 - r1;
                r2 = 1 - r2;
            }
            out.push_back({a + r1 * (b - a) + r2 * (c - a), t, r1, r2});
        }
    }
    return out;
}

Eigen::Vector2f uvAt(const Mesh& mesh, uint32_t t, float b1, float b2)
{
    const Triangle& tri = mesh.triangles[t];
    return (1 - b1 - b2) * mesh.vertices[tri.v[0]].uv + b1 * mesh.vertices[tri.v[1]].uv +
           b2 * mesh.vertices[tri.v[2]].uv;
}

/** Measured reflectivity of a surface point seen from `from` (see lidar_sampler.h). */
float measuredReflectivity(const World& w, const LidarOptions& o, uint32_t t, float b1, float b2,
                           const Eigen::Vector3f& p, const Eigen::Vector3f& from, float noise)
{
    const Triangle& tri = w.mesh.triangles[t];
    const Eigen::Vector3f d = p - from;
    const float range = d.norm();
    const float cos_in = std::abs(w.mesh.vertices[tri.v[0]].n.dot(d)) / std::max(range, 1e-6f);
    const float incidence = static_cast<float>(1 - o.incidence_weight + o.incidence_weight * cos_in);
    const float falloff = 1.f / (1.f + std::pow(range / static_cast<float>(o.range_falloff_m), 2.f));
    const float r = w.materials[tri.material].intrinsicReflectivity(uvAt(w.mesh, t, b1, b2)) * incidence * falloff;
    return std::clamp(r + noise * static_cast<float>(o.reflectivity_noise), 0.f, 1.f);
}
}  // namespace

std::vector<Eigen::Vector3f> chooseStations(const World& world, int count, double height_m)
{
    const Eigen::AlignedBox3f& room = world.room;
    const float z = room.min().z() + static_cast<float>(height_m);
    std::vector<Eigen::Vector3f> candidates;
    for (float x = room.min().x() + 0.5f; x <= room.max().x() - 0.5f; x += 0.5f)
        for (float y = room.min().y() + 0.5f; y <= room.max().y() - 0.5f; y += 0.5f)
        {
            const Eigen::Vector3f c(x, y, z);
            float best2 = 0.25f;  // keep candidates at least 0.5 m from any geometry
            for (const Triangle& t : world.mesh.triangles)
            {
                best2 = std::min(
                    best2, pointTriangleDistanceSquared(c, world.mesh.vertices[t.v[0]].p, world.mesh.vertices[t.v[1]].p,
                                                        world.mesh.vertices[t.v[2]].p));
                if (best2 < 0.25f) break;
            }
            if (best2 >= 0.25f) candidates.push_back(c);
        }
    core::require(!candidates.empty(), "LiDAR stations", "no free position 0.5 m away from the geometry");
    std::vector<Eigen::Vector3f> stations;
    // Start at the candidate closest to the room centre, then farthest-point sampling.
    auto nearest_centre = std::min_element(candidates.begin(), candidates.end(), [&](const auto& a, const auto& b) {
        return (a - room.center()).head(2).squaredNorm() < (b - room.center()).head(2).squaredNorm();
    });
    stations.push_back(*nearest_centre);
    std::vector<float> dist(candidates.size(), 1e30f);
    while (static_cast<int>(stations.size()) < count && stations.size() < candidates.size())
    {
        size_t best = 0;
        for (size_t i = 0; i < candidates.size(); ++i)
        {
            dist[i] = std::min(dist[i], (candidates[i] - stations.back()).squaredNorm());
            if (dist[i] > dist[best]) best = i;
        }
        stations.push_back(candidates[best]);
    }
    return stations;
}

map::LidarMap sampleSurveyMap(const World& w, const LidarOptions& o, uint64_t seed, LidarStats* stats,
                              LidarPointInfo* info)
{
    o.check("[Lidar]");
    std::vector<SurfaceSample> samples = sampleSurfaces(w.mesh, o.density_per_m2, seed);
    const std::vector<Eigen::Vector3f> stations = chooseStations(w, o.num_stations, o.station_height_m);
    for (size_t s = 0; s < stations.size(); ++s)
    {
        CubeMap cube;
        if (o.visibility_from_stations) renderCubeMap(w.mesh, stations[s], o.cubemap_size_px, cube);
        const float pixel_angle = 2.f / o.cubemap_size_px;
        for (SurfaceSample& p : samples)
        {
            const Eigen::Vector3f d = p.p - stations[s];
            const float range = d.norm();
            if (p.station >= 0 && range >= p.range) continue;
            if (o.visibility_from_stations)
            {
                float z_face;
                const VisibilitySample* px = cube.lookup(d, z_face);
                // Visible if the station's z-buffer shows the same triangle, or a surface not in front of
                // the point by more than what a pixel's footprint (up to ~5 pixels at grazing angles) explains.
                const bool visible =
                    px->tri == static_cast<int32_t>(p.tri) || z_face <= px->depth + 0.005f + 5.f * pixel_angle * z_face;
                if (!visible) continue;
            }
            p.station = static_cast<int16_t>(s);
            p.range = range;
        }
    }
    std::mt19937_64 rng(seed ^ 0x11DA5ull);
    std::normal_distribution<float> normal(0.f, 1.f);
    map::LidarMap map;
    map.reserve(samples.size());
    LidarStats st;
    st.sampled = samples.size();
    st.stations = stations;
    if (info) *info = {};
    for (const SurfaceSample& p : samples)
    {
        if (p.station < 0)
        {
            ++st.not_visible;
            continue;
        }
        const Eigen::Vector3f from = stations[p.station];
        const Eigen::Vector3f dir = (p.p - from) / std::max(p.range, 1e-6f);
        const Eigen::Vector3f q = p.p + dir * (normal(rng) * static_cast<float>(o.range_noise_mm * 1e-3));
        const float refl = measuredReflectivity(w, o, p.tri, p.b1, p.b2, p.p, from, normal(rng));
        map.addPoint(q.x(), q.y(), q.z(), refl);
        if (info)
        {
            const uint16_t m = w.mesh.triangles[p.tri].material;
            info->albedo.push_back(w.materials[m].albedo(uvAt(w.mesh, p.tri, p.b1, p.b2), 0.f));
            info->material.push_back(m);
        }
    }
    st.kept = map.size();
    if (stats) *stats = st;
    return map;
}

map::LidarMap sampleBeamMap(const World& w, const LidarOptions& o, uint64_t seed, LidarStats* stats)
{
    o.check("[Lidar]");
    const std::vector<Eigen::Vector3f> stations = chooseStations(w, o.beam_num_scans, o.station_height_m - 0.4);
    std::mt19937_64 rng(seed ^ 0xB3A4ull);
    std::normal_distribution<float> normal(0.f, 1.f);
    map::LidarMap map;
    LidarStats st;
    st.stations = stations;
    const int beams = 32;
    for (const Eigen::Vector3f& station : stations)
    {
        CubeMap cube;
        renderCubeMap(w.mesh, station, std::min(o.cubemap_size_px, 1024), cube);
        for (int b = 0; b < beams; ++b)
        {
            const double elev =
                (o.beam_min_elevation_deg + (o.beam_max_elevation_deg - o.beam_min_elevation_deg) * b / (beams - 1)) *
                M_PI / 180;
            for (int a = 0; a < o.beam_azimuth_steps; ++a)
            {
                const double az = 2 * M_PI * a / o.beam_azimuth_steps;
                const Eigen::Vector3f d(static_cast<float>(std::cos(elev) * std::cos(az)),
                                        static_cast<float>(std::cos(elev) * std::sin(az)),
                                        static_cast<float>(std::sin(elev)));
                float z_face;
                const VisibilitySample* px = cube.lookup(d, z_face);
                ++st.sampled;
                if (px->tri < 0) continue;
                const float range = px->depth / z_face + normal(rng) * static_cast<float>(o.beam_range_noise_mm * 1e-3);
                const Eigen::Vector3f q = station + d * range;
                const float refl =
                    measuredReflectivity(w, o, static_cast<uint32_t>(px->tri), px->b1, px->b2, q, station, normal(rng));
                map.addPoint(q.x(), q.y(), q.z(), refl);
            }
        }
    }
    st.kept = map.size();
    if (stats) *stats = st;
    return map;
}

}  // namespace quasiloc::sim
