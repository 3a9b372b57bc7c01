// How close a map is to the simulated world's true surfaces (lidar_sweeps.h evaluateSweptMap).
#include <algorithm>
#include <cmath>
#include <quasiloc/sim/lidar_sweeps.h>
#include <random>
#include <unordered_map>

namespace quasiloc::sim
{
namespace
{
constexpr float kCap_m = 0.1f;  ///< distances are searched up to this

int64_t cellKey(int x, int y, int z)
{
    return (int64_t(x) << 42) ^ (int64_t(y + (1 << 20)) << 21) ^ int64_t(z + (1 << 20));
}

/** Distance from a point to the nearest triangle of a mesh, up to kCap_m: triangles listed in every 0.2 m cell their
 *  box (grown by kCap_m) overlaps, sorted by cell. */
class TriangleDistance
{
   public:
    explicit TriangleDistance(const Mesh& mesh) : mesh_(mesh)
    {
        for (uint32_t t = 0; t < mesh.triangles.size(); ++t)
        {
            Eigen::AlignedBox3f box;
            for (uint32_t v : mesh.triangles[t].v) box.extend(mesh.vertices[v].p);
            const Eigen::Vector3i lo = cell(box.min().array() - kCap_m), hi = cell(box.max().array() + kCap_m);
            for (int x = lo.x(); x <= hi.x(); ++x)
                for (int y = lo.y(); y <= hi.y(); ++y)
                    for (int z = lo.z(); z <= hi.z(); ++z) entries_.emplace_back(cellKey(x, y, z), t);
        }
        std::sort(entries_.begin(), entries_.end());
    }

    float distance(const Eigen::Vector3f& p) const
    {
        const Eigen::Vector3i c = cell(p);
        const int64_t key = cellKey(c.x(), c.y(), c.z());
        auto it = std::lower_bound(entries_.begin(), entries_.end(), std::make_pair(key, uint32_t(0)));
        float best2 = kCap_m * kCap_m;
        for (; it != entries_.end() && it->first == key; ++it)
        {
            const Triangle& tri = mesh_.triangles[it->second];
            best2 =
                std::min(best2, pointTriangleDistanceSquared(p, mesh_.vertices[tri.v[0]].p, mesh_.vertices[tri.v[1]].p,
                                                             mesh_.vertices[tri.v[2]].p));
        }
        return std::sqrt(best2);
    }

   private:
    static Eigen::Vector3i cell(const Eigen::Vector3f& p) { return (p / 0.2f).array().floor().cast<int>(); }
    const Mesh& mesh_;
    std::vector<std::pair<int64_t, uint32_t>> entries_;
};

/** Is there a map point within `radius` (<= 5 cm) of p? */
class PointHash
{
   public:
    explicit PointHash(const map::LidarMap& m)
    {
        for (size_t i = 0; i < m.size(); ++i)
        {
            const Eigen::Vector3f p = m.point(i);
            cells_[key(p)].push_back(p);
        }
    }
    bool near(const Eigen::Vector3f& p, float radius) const
    {
        const Eigen::Vector3i c = (p / 0.05f).array().floor().cast<int>();
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -1; dz <= 1; ++dz)
                {
                    const auto it = cells_.find(cellKey(c.x() + dx, c.y() + dy, c.z() + dz));
                    if (it == cells_.end()) continue;
                    for (const Eigen::Vector3f& q : it->second)
                        if ((q - p).squaredNorm() <= radius * radius) return true;
                }
        return false;
    }

   private:
    static int64_t key(const Eigen::Vector3f& p)
    {
        const Eigen::Vector3i c = (p / 0.05f).array().floor().cast<int>();
        return cellKey(c.x(), c.y(), c.z());
    }
    std::unordered_map<int64_t, std::vector<Eigen::Vector3f>> cells_;
};

enum class Transient
{
    none,
    person,
    furniture
};

Transient transientAt(const MappingScene& scene, const Eigen::Vector3f& p)
{
    for (const Person& person : scene.people)
    {
        const Eigen::Vector2f ab = person.b - person.a, ap = p.head<2>() - person.a;
        const float s = ab.squaredNorm() > 0 ? std::clamp(ap.dot(ab) / ab.squaredNorm(), 0.f, 1.f) : 0.f;
        if ((ap - s * ab).norm() <= person.radius_m + 0.1f && p.z() <= scene.floor_z + person.height_m + 0.1f)
            return Transient::person;
    }
    for (const MovedFurniture& f : scene.furniture)
        for (int after = 0; after <= int(f.moved); ++after)
        {
            const Eigen::Matrix3f R =
                Eigen::AngleAxisf(after ? f.yaw_after : f.yaw_before, Eigen::Vector3f::UnitZ()).toRotationMatrix();
            const Eigen::Vector3f local = R.transpose() * (p - (after ? f.centre_after : f.centre_before));
            if ((local.cwiseAbs().array() <= 0.5f * f.size.array() + 0.05f).all()) return Transient::furniture;
        }
    return Transient::none;
}

bool onPaneInterior(const GlassPane& g, const Eigen::Vector3f& p)
{
    const Eigen::Vector3f d = p - g.origin;
    if (std::abs(d.dot(g.normal)) > 0.03f) return false;
    const float s = d.dot(g.u) / g.u.squaredNorm(), t = d.dot(g.v) / g.v.squaredNorm();
    const float ms = 0.05f / g.u.norm(), mt = 0.05f / g.v.norm();
    return s >= ms && s <= 1 - ms && t >= mt && t <= 1 - mt;
}

/** Which part of the world a surface sample belongs to (SweptMapQuality::coverage_by_part). */
int surfacePart(const World& world, const Eigen::Vector3f& p)
{
    const Eigen::AlignedBox3f& room = world.room;
    if (p.z() < room.min().z() + 0.03f) return 0;  // floor
    if (p.z() > room.max().z() - 0.03f) return 1;  // ceiling
    const Eigen::Vector3f to_min = p - room.min(), to_max = room.max() - p;
    if (std::min({to_min.x(), to_min.y(), to_max.x(), to_max.y()}) < 0.03f) return 2;  // outer walls
    return 3;                                                                          // the rest
}

/** Surface samples of the mesh, about `per_m2` per square metre (deterministic). */
std::vector<Eigen::Vector3f> surfaceSamples(const Mesh& mesh, double per_m2)
{
    std::vector<Eigen::Vector3f> out;
    std::mt19937 rng(12345);
    std::uniform_real_distribution<float> u01(0.f, 1.f);
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
    {
        const double expected = mesh.triangleArea(t) * per_m2;
        const auto n = size_t(expected) + (u01(rng) < expected - std::floor(expected) ? 1 : 0);
        const Triangle& tri = mesh.triangles[t];
        for (size_t i = 0; i < n; ++i)
        {
            float r1 = u01(rng), r2 = u01(rng);
            if (r1 + r2 > 1) r1 = 1 - r1, r2 = 1 - r2;
            const Eigen::Vector3f a = mesh.vertices[tri.v[0]].p;
            out.push_back(a + r1 * (mesh.vertices[tri.v[1]].p - a) + r2 * (mesh.vertices[tri.v[2]].p - a));
        }
    }
    return out;
}
}  // namespace

SweptMapQuality evaluateSweptMap(const World& world, const MappingScene& scene, const map::LidarMap& map,
                                 const map::LidarMap& removed)
{
    SweptMapQuality q;
    q.points = map.size();
    const TriangleDistance surfaces(world.mesh);
    std::vector<float> error;
    error.reserve(map.size());
    size_t beyond = 0;
    auto transient = [&](const Eigen::Vector3f& p, float dist) {
        return dist > 0.05f ? transientAt(scene, p) : Transient::none;
    };
    for (size_t i = 0; i < map.size(); ++i)
    {
        const Eigen::Vector3f p = map.point(i);
        const float d = surfaces.distance(p);
        error.push_back(d);
        beyond += d >= kCap_m;
        const Transient kind = transient(p, d);
        q.person_points_fused += kind == Transient::person;
        q.furniture_points_fused += kind == Transient::furniture;
        q.glass_points += std::any_of(scene.glass.begin(), scene.glass.end(),
                                      [&](const GlassPane& g) { return onPaneInterior(g, p); });
    }
    for (size_t i = 0; i < removed.size(); ++i)
    {
        const Eigen::Vector3f p = removed.point(i);
        const Transient kind = transient(p, surfaces.distance(p));
        q.person_points_removed += kind == Transient::person;
        q.furniture_points_removed += kind == Transient::furniture;
    }
    q.person_points_fused += q.person_points_removed;
    q.furniture_points_fused += q.furniture_points_removed;
    if (!error.empty())
    {
        auto quantile = [&](double f) {
            const size_t k = std::min(error.size() - 1, size_t(f * double(error.size())));
            std::nth_element(error.begin(), error.begin() + long(k), error.end());
            return double(error[k]);
        };
        q.median_error_m = quantile(0.5);
        q.p95_error_m = quantile(0.95);
        q.share_beyond_10cm = double(beyond) / double(error.size());
    }
    const PointHash points(map);
    const std::vector<Eigen::Vector3f> samples = surfaceSamples(world.mesh, 50);
    size_t covered = 0, part_covered[4] = {0, 0, 0, 0}, part_samples[4] = {0, 0, 0, 0};
    for (const Eigen::Vector3f& s : samples)
    {
        const bool near = points.near(s, 0.05f);
        const int part = surfacePart(world, s);
        covered += near;
        part_covered[part] += near;
        ++part_samples[part];
    }
    q.coverage = samples.empty() ? 0 : double(covered) / double(samples.size());
    for (int k = 0; k < 4; ++k)
        q.coverage_by_part[k] = part_samples[k] ? double(part_covered[k]) / double(part_samples[k]) : 0;
    return q;
}

}  // namespace quasiloc::sim
