#include <algorithm>
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/map/gmm.h>
#include <quasiloc/map/gmm_surface.h>
#include <quasiloc/sim/clearance_grid.h>
#include <quasiloc/sim/world_builder.h>
#include <random>

namespace quasiloc::sim
{
namespace
{
using Rng = std::mt19937_64;

double percentile(std::vector<double> v, double p)
{
    std::sort(v.begin(), v.end());
    return v[static_cast<size_t>(std::clamp(p, 0.0, 1.0) * (v.size() - 1))];
}

Eigen::AlignedBox3f roomExtent(const std::vector<map::GmmComponent>& gmm, const std::vector<LineSegment3D>& lines)
{
    std::vector<double> xs, ys, zs, line_z;
    for (const auto& c : gmm)
    {
        xs.push_back(c.mean.x());
        ys.push_back(c.mean.y());
        zs.push_back(c.mean.z());
    }
    for (const auto& l : lines)
    {
        line_z.push_back(l.a.z());
        line_z.push_back(l.b.z());
    }
    const float ceiling = static_cast<float>(std::max(percentile(line_z, 0.995), percentile(zs, 0.995)));
    return Eigen::AlignedBox3f(Eigen::Vector3f(percentile(xs, 0.005), percentile(ys, 0.005), percentile(zs, 0.005)),
                               Eigen::Vector3f(percentile(xs, 0.995), percentile(ys, 0.995), ceiling));
}

/** The shell: floor, ceiling, and walls cut into ~2 m sections of varying material. */
void addShell(const Eigen::AlignedBox3f& room, float cell, Rng& rng, Mesh& mesh)
{
    const Eigen::Vector3f lo = room.min(), hi = room.max(), size = hi - lo;
    mesh.addQuad(lo, Eigen::Vector3f(size.x(), 0, 0), Eigen::Vector3f(0, size.y(), 0), kFloorCarpet, cell);
    mesh.addQuad(Eigen::Vector3f(lo.x(), lo.y(), hi.z()), Eigen::Vector3f(size.x(), 0, 0),
                 Eigen::Vector3f(0, size.y(), 0), kCeilingPanels, cell);
    const uint16_t wall_materials[] = {kWallPlaster, kCurtain, kWoodPanel, kConcrete, kWallPlaster, kCurtain};
    std::uniform_int_distribution<int> pick(0, 5);
    const Eigen::Vector3f corners[4] = {
        lo, {hi.x(), lo.y(), lo.z()}, {hi.x(), hi.y(), lo.z()}, {lo.x(), hi.y(), lo.z()}};
    float u_along = 0;
    for (int w = 0; w < 4; ++w)
    {
        const Eigen::Vector3f a = corners[w], b = corners[(w + 1) % 4];
        const float len = (b - a).norm();
        const int sections = std::max(1, static_cast<int>(std::round(len / 2.0f)));
        for (int s = 0; s < sections; ++s)
        {
            const Eigen::Vector3f p0 = a + (b - a) * (static_cast<float>(s) / sections);
            mesh.addQuad(p0, (b - a) / sections, Eigen::Vector3f(0, 0, size.z()), wall_materials[pick(rng)], cell,
                         Eigen::Vector2f(u_along, 0));
            u_along += len / sections;
        }
    }
}

float distanceToShell(const Eigen::Vector3f& p, const Eigen::AlignedBox3f& room)
{
    const Eigen::Vector3f d_lo = p - room.min(), d_hi = room.max() - p;
    return std::min(d_lo.minCoeff(), d_hi.minCoeff());
}

void addGmmPatches(const std::vector<map::GmmComponent>& gmm, const Eigen::AlignedBox3f& room, const WorldOptions& o,
                   const ClearanceGrid& grid, Rng& rng, Mesh& mesh, WorldStats& st)
{
    const uint16_t horizontal[] = {kMattress, kCardboard, kWoodPanel, kConcrete};
    const uint16_t vertical[] = {kWoodPanel, kCardboard, kPoster, kConcrete, kMattress, kCurtain};
    std::uniform_real_distribution<float> uv(0.f, 10.f);
    const uint64_t material_salt = rng();
    for (const map::GmmComponent& c : gmm)
    {
        const Eigen::Vector3f mean = c.mean.cast<float>();
        if (distanceToShell(mean, room) < o.shell_margin_m || !room.contains(mean))
        {
            ++st.gmm_shell;
            continue;
        }
        const map::GmmComponentSurface surface = map::componentSurface(c, o.gmm_sigma_scale);
        float su = static_cast<float>(surface.semi_u_m);
        float sv = static_cast<float>(surface.semi_v_m);
        if (su < o.gmm_min_semi_axis_m)
        {
            ++st.gmm_small;
            continue;
        }
        su = std::min(su, static_cast<float>(o.gmm_max_semi_axis_m));
        sv = std::clamp(sv, static_cast<float>(o.gmm_min_semi_axis_m), su);
        const Eigen::Vector3f n = surface.normal.cast<float>();
        const Eigen::Vector3f au = surface.axis_u.cast<float>().normalized();
        const Eigen::Vector3f av = n.cross(au).normalized();
        const bool is_horizontal = std::abs(n.z()) > 0.8f;
        // Neighbouring patches usually belong to one object: the material is a hash of the 1 m cell of the
        // mean (and of the seed), so clusters look like coherent objects instead of a patchwork.
        const Eigen::Vector3i cell = (mean / 1.0f).array().floor().cast<int>();
        uint64_t h = (static_cast<uint64_t>(cell.x() + 1000) * 73856093ull) ^
                     (static_cast<uint64_t>(cell.y() + 1000) * 19349663ull) ^
                     (static_cast<uint64_t>(cell.z() + 1000) * 83492791ull) ^ material_salt;
        h ^= h >> 17;
        const uint16_t mat = is_horizontal ? horizontal[h % 4] : vertical[h % 6];
        const Eigen::Vector2f uv_offset(uv(rng), uv(rng));
        bool placed = false;
        for (int attempt = 0; attempt < 4 && !placed; ++attempt)
        {
            Mesh piece;
            piece.addEllipse(mean, au, av, su, sv, mat, static_cast<float>(o.max_cell_m), uv_offset);
            placed = placeIfClear(piece, grid, static_cast<float>(o.clearance_m), mesh);
            if (!placed)
            {
                su *= 0.6f;
                sv *= 0.6f;
            }
            else if (attempt > 0)
                ++st.gmm_shrunk;
        }
        placed ? ++st.gmm_patches : ++st.gmm_dropped;
    }
}

Eigen::Matrix3f yawRotation(float yaw) { return Eigen::AngleAxisf(yaw, Eigen::Vector3f::UnitZ()).toRotationMatrix(); }

void addObjects(const Eigen::AlignedBox3f& room, const WorldOptions& o, const ClearanceGrid& grid, Rng& rng, Mesh& mesh,
                WorldStats& st)
{
    std::uniform_real_distribution<float> u01(0.f, 1.f);
    const Eigen::Vector3f lo = room.min(), size = room.sizes();
    const float cell = static_cast<float>(o.max_cell_m), clear = static_cast<float>(o.clearance_m);
    auto floor_point = [&](float margin) {
        return Eigen::Vector3f(lo.x() + margin + u01(rng) * (size.x() - 2 * margin),
                               lo.y() + margin + u01(rng) * (size.y() - 2 * margin), lo.z());
    };
    auto try_place = [&](int count, const auto& make) {
        for (int placed = 0, attempts = 0; placed < count && attempts < 40 * count; ++attempts)
        {
            Mesh piece;
            make(piece);
            if (placeIfClear(piece, grid, clear, mesh))
            {
                ++placed;
                ++st.objects_placed;
            }
            else
                ++st.objects_rejected;
        }
    };
    try_place(o.num_boxes, [&](Mesh& m) {  // cardboard boxes, sometimes stacked two high
        const Eigen::Vector3f s(0.3f + 0.6f * u01(rng), 0.3f + 0.6f * u01(rng), 0.25f + 0.55f * u01(rng));
        Eigen::Vector3f c = floor_point(0.5f);
        c.z() += 0.5f * s.z();
        const Eigen::Matrix3f R = yawRotation(u01(rng) * 3.14159f);
        m.addBox(c, R, s, kCardboard, cell, Eigen::Vector2f(u01(rng) * 5, u01(rng) * 5));
        if (u01(rng) < 0.4f)
            m.addBox(c + Eigen::Vector3f(0, 0, 0.5f * s.z() + 0.2f), R,
                     Eigen::Vector3f(0.8f * s.x(), 0.8f * s.y(), 0.4f), kCardboard, cell,
                     Eigen::Vector2f(u01(rng) * 5, u01(rng) * 5));
    });
    try_place(o.num_slabs, [&](Mesh& m) {  // mattresses lying flat or leaning against something
        const Eigen::Vector3f s(1.9f, 0.9f + 0.4f * u01(rng), 0.15f + 0.1f * u01(rng));
        Eigen::Vector3f c = floor_point(1.0f);
        Eigen::Matrix3f R = yawRotation(u01(rng) * 3.14159f);
        if (u01(rng) < 0.5f)
        {
            R = R * Eigen::AngleAxisf(1.2f, Eigen::Vector3f::UnitY()).toRotationMatrix();
            c.z() += 0.85f;
        }
        else
            c.z() += 0.5f * s.z();
        m.addBox(c, R, s, kMattress, cell, Eigen::Vector2f(u01(rng) * 5, u01(rng) * 5));
    });
    try_place(o.num_poles, [&](Mesh& m) {  // floor-to-ceiling poles with reflective tape
        m.addCylinder(floor_point(0.3f), 0.04f + 0.04f * u01(rng), size.z(), 10, kMetalPole, cell);
    });
    try_place(o.num_wall_posters, [&](Mesh& m) {  // posters and calibration boards 1 cm off a wall
        const int wall = static_cast<int>(u01(rng) * 4) % 4;
        const float w = 0.6f + 0.8f * u01(rng), h = 0.5f + 0.6f * u01(rng), z = 0.4f + u01(rng) * (size.z() - 1.4f);
        const bool along_x = wall < 2;
        const float len = along_x ? size.x() : size.y();
        const float s0 = 0.2f + u01(rng) * std::max(0.f, len - w - 0.4f);
        Eigen::Vector3f origin, axis;
        if (along_x)
        {
            origin = Eigen::Vector3f(lo.x() + s0, wall == 0 ? lo.y() + 0.01f : room.max().y() - 0.01f, lo.z() + z);
            axis = Eigen::Vector3f(w, 0, 0);
        }
        else
        {
            origin = Eigen::Vector3f(wall == 2 ? lo.x() + 0.01f : room.max().x() - 0.01f, lo.y() + s0, lo.z() + z);
            axis = Eigen::Vector3f(0, w, 0);
        }
        m.addQuad(origin, axis, Eigen::Vector3f(0, 0, h), u01(rng) < 0.7f ? kPoster : kCheckerBoard, cell,
                  Eigen::Vector2f(u01(rng) * 5, u01(rng) * 5));
    });
}

void addLights(const Eigen::AlignedBox3f& room, const WorldOptions& o, World& w)
{
    const int nx = o.num_lights >= 4 ? (o.num_lights + 1) / 2 : o.num_lights, ny = o.num_lights >= 4 ? 2 : 1;
    const Eigen::Vector3f lo = room.min(), size = room.sizes();
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx && static_cast<int>(w.lights.size()) < o.num_lights; ++i)
        {
            PointLight l;
            l.position = Eigen::Vector3f(lo.x() + size.x() * (i + 0.5f) / nx, lo.y() + size.y() * (j + 0.5f) / ny,
                                         room.max().z() - 0.4f);
            l.intensity = static_cast<float>(o.light_intensity);
            w.lights.push_back(l);
        }
}
}  // namespace

std::string roomName(ViconRoom room)
{
    return room == ViconRoom::office_floor ? "floor"
           : room == ViconRoom::campus     ? "campus"
           : room == ViconRoom::v1         ? "v1"
                                           : "v2";
}

std::string gmmPath(const std::string& shared_dir, const std::string& world)
{
    return shared_dir + "/data/euroc/maps/gmm/" + world + ".gmm";
}
std::string linesPath(const std::string& shared_dir, const std::string& world)
{
    return shared_dir + "/data/euroc/maps/lines/" + world + "_line_3d.txt";
}

std::vector<std::string> roomSequences(const std::string& world)
{
    core::require(world == "v1" || world == "v2", "World.world", "must be v1 or v2, got '" + world + "'");
    const std::string p = world == "v1" ? "V1_0" : "V2_0";
    return {p + "1_easy", p + "2_medium", p + "3_difficult"};
}

std::vector<Eigen::Vector3f> loadRoomTrajectoryPositions(const std::string& shared_dir, const std::string& world)
{
    std::vector<Eigen::Vector3f> out;
    for (const std::string& seq : roomSequences(world))
    {
        const core::Trajectory traj = core::readTum(shared_dir + "/data/euroc/groundtruth/cam0/" + seq + ".txt");
        for (const auto& tp : traj.poses)
            out.emplace_back(static_cast<float>(tp.pose.x()), static_cast<float>(tp.pose.y()),
                             static_cast<float>(tp.pose.z()));
    }
    return out;
}

World buildWorld(const WorldOptions& o, const std::string& shared_dir, uint64_t seed,
                 const std::vector<Eigen::Vector3f>& keep_clear, WorldStats* stats_out)
{
    o.check("[World]");
    core::require(o.world != ViconRoom::office_floor, "[World] world",
                  "floor is built by buildFloorWorld (floor_world.h), not from EuRoC room data");
    core::require(o.world != ViconRoom::campus, "[World] world",
                  "campus is built by buildCampusWorld (campus_world.h), not from EuRoC room data");
    const std::string room = roomName(o.world);
    const std::vector<map::GmmComponent> gmm = map::readGmmFile(gmmPath(shared_dir, room));
    const std::vector<LineSegment3D> lines = readLineSegments(linesPath(shared_dir, room));
    Rng rng = worldRng(seed);
    World w = startWorld(o, seed, room);
    WorldStats st;
    w.room = roomExtent(gmm, lines);
    const ClearanceGrid grid(keep_clear, 0.5f);
    addShell(w.room, static_cast<float>(o.max_cell_m), rng, w.mesh);
    st.gmm_components = gmm.size();
    if (o.gmm_patches) addGmmPatches(gmm, w.room, o, grid, rng, w.mesh, st);
    addObjects(w.room, o, grid, rng, w.mesh, st);
    addLights(w.room, o, w);
    finishWorld(w, grid, o.shadow_map_px, st, stats_out);
    return w;
}

World startWorld(const WorldOptions& o, uint64_t seed, const std::string& name)
{
    World w;
    w.name = name;
    w.materials = makeMaterials(o.materials, seed, o.texture_size_px);
    w.ambient = static_cast<float>(o.ambient);
    return w;
}

std::mt19937_64 worldRng(uint64_t seed) { return Rng(seed * 6364136223846793005ull + 1442695040888963407ull); }

bool placeIfClear(const Mesh& piece, const ClearanceGrid& grid, float clearance, Mesh& mesh)
{
    if (grid.minDistance(piece, clearance) < clearance) return false;
    mesh.append(piece);
    return true;
}

bool placeIfClear(const Mesh& piece, const ClearanceGrid& grid, float clearance, Mesh& mesh, WorldStats& st)
{
    const bool placed = placeIfClear(piece, grid, clearance, mesh);
    ++(placed ? st.objects_placed : st.objects_rejected);
    return placed;
}

void finishWorld(World& w, const ClearanceGrid& grid, int shadow_map_px, WorldStats& st, WorldStats* stats_out)
{
    w.computeIrradiance(shadow_map_px);
    st.triangles = w.mesh.triangles.size();
    st.vertices = w.mesh.vertices.size();
    st.area_m2 = w.mesh.area();
    st.min_clearance_m = grid.empty() ? 0.0 : grid.minDistance(w.mesh, 5.f);
    if (stats_out) *stats_out = st;
}

double minClearance(const Mesh& mesh, const std::vector<Eigen::Vector3f>& positions, double max_search_m)
{
    const ClearanceGrid grid(positions, 0.5f);
    return grid.minDistance(mesh, static_cast<float>(max_search_m));
}

}  // namespace quasiloc::sim
