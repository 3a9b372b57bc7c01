// What the mapping run sees that the camera does not: people, furniture moved or gone since, glass (lidar_sweeps.h).
#include <algorithm>
#include <cmath>
#include <quasiloc/sim/lidar_sweeps.h>
#include <random>

namespace quasiloc::sim
{
namespace
{
/** Free floor positions: places where an upright cylinder of some radius stands clear of the walls and the clutter
 *  (floor and ceiling triangles not counted), on a 0.25 m grid. */
class FreeFloor
{
   public:
    explicit FreeFloor(const World& world) : world_(world)
    {
        const float floor_z = world.room.min().z(), ceiling_z = world.room.max().z();
        for (uint32_t t = 0; t < world.mesh.triangles.size(); ++t)
        {
            Eigen::AlignedBox3f box;
            for (uint32_t v : world.mesh.triangles[t].v) box.extend(world.mesh.vertices[v].p);
            if (box.max().z() < floor_z + 0.03f || box.min().z() > ceiling_z - 0.03f) continue;
            tris_.push_back(t);
            boxes_.push_back(box);
        }
    }

    /** Is a vertical cylinder of `radius` around (x, y), from 0.1 m above the floor to `height`, clear? */
    bool clear(const Eigen::Vector2f& xy, float radius, float height) const
    {
        const float z0 = world_.room.min().z() + 0.1f, z1 = world_.room.min().z() + height;
        if (!world_.room.contains(Eigen::Vector3f(xy.x(), xy.y(), z0))) return false;
        const float r2 = radius * radius;
        for (size_t i = 0; i < tris_.size(); ++i)
        {
            const Eigen::AlignedBox3f& b = boxes_[i];
            if (b.min().x() > xy.x() + radius || b.max().x() < xy.x() - radius || b.min().y() > xy.y() + radius ||
                b.max().y() < xy.y() - radius || b.min().z() > z1 || b.max().z() < z0)
                continue;
            const Triangle& tri = world_.mesh.triangles[tris_[i]];
            for (float z = z0; z <= z1 + 1e-3f; z += std::max(0.1f, (z1 - z0) / 4))
                if (pointTriangleDistanceSquared(Eigen::Vector3f(xy.x(), xy.y(), z), world_.mesh.vertices[tri.v[0]].p,
                                                 world_.mesh.vertices[tri.v[1]].p,
                                                 world_.mesh.vertices[tri.v[2]].p) < r2)
                    return false;
        }
        return true;
    }

    std::vector<Eigen::Vector2f> candidates(float radius, float height) const
    {
        std::vector<Eigen::Vector2f> out;
        const Eigen::AlignedBox3f& room = world_.room;
        for (float x = room.min().x() + radius; x <= room.max().x() - radius; x += 0.25f)
            for (float y = room.min().y() + radius; y <= room.max().y() - radius; y += 0.25f)
                if (clear({x, y}, radius, height)) out.emplace_back(x, y);
        return out;
    }

   private:
    const World& world_;
    std::vector<uint32_t> tris_;
    std::vector<Eigen::AlignedBox3f> boxes_;
};

float distanceToRun(const MappingRun& run, const Eigen::Vector2f& xy)
{
    float best = 1e9f;
    for (size_t i = 0; i < run.T_world_lidar.size(); i += 10)
        best = std::min(best, (run.T_world_lidar[i].translation().head<2>().cast<float>() - xy).norm());
    return best;
}

std::vector<GlassPane> windowPanes(const World& world, int count, std::mt19937_64& rng)
{
    std::vector<GlassPane> panes;
    const Eigen::AlignedBox3f& room = world.room;
    std::uniform_real_distribution<float> u01(0.f, 1.f);
    for (int i = 0; i < count; ++i)
    {
        const int wall = i % 4;  // -x, +x, -y, +y: one window per wall before a second one
        const bool along_y = wall < 2;
        const float lo = along_y ? room.min().y() : room.min().x(), hi = along_y ? room.max().y() : room.max().x();
        const float width = std::min(1.2f, 0.5f * (hi - lo));
        const float start = lo + 0.5f + u01(rng) * std::max(0.f, hi - lo - 1.f - width);
        GlassPane g;
        const float fixed = wall == 0   ? room.min().x()
                            : wall == 1 ? room.max().x()
                            : wall == 2 ? room.min().y()
                                        : room.max().y();
        g.origin = along_y ? Eigen::Vector3f(fixed, start, room.min().z() + 0.9f)
                           : Eigen::Vector3f(start, fixed, room.min().z() + 0.9f);
        g.u = along_y ? Eigen::Vector3f(0, width, 0) : Eigen::Vector3f(width, 0, 0);
        g.v = Eigen::Vector3f(0, 0, std::min(1.2f, room.sizes().z() - 1.1f));
        g.normal = along_y ? Eigen::Vector3f::UnitX() : Eigen::Vector3f::UnitY();
        panes.push_back(g);
    }
    return panes;
}
}  // namespace

Eigen::Vector2f Person::at(double t) const
{
    const float len = std::max(1e-3f, (b - a).norm());
    const double period = 2 * len / speed_m_s;
    const double x = std::fmod(t + phase_s, period) / period;  // 0 -> a, 0.5 -> b, 1 -> a
    const float f = float(x < 0.5 ? 2 * x : 2 - 2 * x);
    return a + f * (b - a);
}

bool GlassPane::contains(const Eigen::Vector3f& p) const
{
    const Eigen::Vector3f d = p - origin;
    if (std::abs(d.dot(normal)) > 0.03f) return false;
    const float s = d.dot(u) / u.squaredNorm(), t = d.dot(v) / v.squaredNorm();
    return s >= 0 && s <= 1 && t >= 0 && t <= 1;
}

bool MappingScene::onGlass(const Eigen::Vector3f& p) const
{
    return std::any_of(glass.begin(), glass.end(), [&](const GlassPane& g) { return g.contains(p); });
}

Mesh MappingScene::meshAt(double t) const
{
    Mesh mesh;
    for (const Person& p : people)
    {
        const Eigen::Vector2f xy = p.at(t);
        mesh.addCylinder(Eigen::Vector3f(xy.x(), xy.y(), floor_z), p.radius_m, p.height_m, 12, kPersonClothes, 0.3f);
    }
    for (const MovedFurniture& f : furniture)
    {
        const bool after = f.moved && t >= 0.5 * run_duration_s;
        const Eigen::Matrix3f R =
            Eigen::AngleAxisf(after ? f.yaw_after : f.yaw_before, Eigen::Vector3f::UnitZ()).toRotationMatrix();
        mesh.addBox(after ? f.centre_after : f.centre_before, R, f.size, f.material, 0.3f);
    }
    return mesh;
}

MappingScene makeMappingScene(const World& world, const MappingRun& run, const LidarOptions& o, uint64_t seed)
{
    MappingScene scene;
    scene.run_duration_s = run.duration();
    scene.floor_z = world.room.min().z();
    std::mt19937_64 rng(seed ^ 0x5CE4Eull);
    std::uniform_real_distribution<float> u01(0.f, 1.f);
    scene.glass = windowPanes(world, o.sweep_glass_panes, rng);
    if (o.sweep_people == 0 && o.sweep_furniture == 0) return scene;
    const FreeFloor free(world);
    const std::vector<Eigen::Vector2f> spots = free.candidates(0.35f, 1.8f);
    auto pick = [&](const std::vector<Eigen::Vector2f>& from) {
        return from[size_t(u01(rng) * from.size()) % from.size()];
    };
    for (int i = 0; i < o.sweep_people && !spots.empty(); ++i)
    {
        Person p;
        p.a = pick(spots);
        p.b = p.a;
        for (int attempt = 0; attempt < 50; ++attempt)  // the farthest free spot 2-5 m away on a free line
        {
            const Eigen::Vector2f b = pick(spots);
            const float len = (b - p.a).norm();
            if (len < 2.f || len > 5.f || len <= (p.b - p.a).norm()) continue;
            bool line_clear = true;
            for (float s = 0.25f; s < len && line_clear; s += 0.25f)
                line_clear = free.clear(p.a + s / len * (b - p.a), 0.3f, 1.8f);
            if (line_clear) p.b = b;
        }
        p.speed_m_s = 0.8f + 0.6f * u01(rng);
        p.phase_s = 20 * u01(rng);
        p.height_m = 1.6f + 0.25f * u01(rng);
        scene.people.push_back(p);
    }
    struct Kind
    {
        Eigen::Vector3f size;
        uint16_t material;
    };
    const Kind kinds[] = {{{0.5f, 0.5f, 0.9f}, kWoodPanel},   // chair
                          {{1.2f, 0.7f, 0.75f}, kWoodPanel},  // table
                          {{0.8f, 0.45f, 1.2f}, kCardboard},  // cabinet / box stack
                          {{0.6f, 0.6f, 0.6f}, kCardboard}};
    for (int i = 0; i < o.sweep_furniture; ++i)
    {
        const Kind& k = kinds[i % 4];
        const float radius = 0.5f * k.size.head<2>().norm() + 0.05f;
        std::vector<Eigen::Vector2f> places;
        for (const Eigen::Vector2f& c : free.candidates(radius, k.size.z()))
            if (distanceToRun(run, c) > radius + 0.6f) places.push_back(c);
        if (places.size() < 2) continue;
        MovedFurniture f;
        f.size = k.size;
        f.material = k.material;
        const Eigen::Vector2f before = pick(places), after = pick(places);
        f.centre_before = Eigen::Vector3f(before.x(), before.y(), scene.floor_z + 0.5f * k.size.z());
        f.centre_after = Eigen::Vector3f(after.x(), after.y(), scene.floor_z + 0.5f * k.size.z());
        f.yaw_before = float(M_PI) * u01(rng);
        f.yaw_after = float(M_PI) * u01(rng);
        f.moved = i % 2 == 1;
        scene.furniture.push_back(f);
    }
    return scene;
}

}  // namespace quasiloc::sim
