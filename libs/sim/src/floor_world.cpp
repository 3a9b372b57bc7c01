// The office floor of the ground robot (floor_world.h): layout from a seed, then walls, clutter and lights.
#include <algorithm>
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/sim/clearance_grid.h>
#include <quasiloc/sim/floor_world.h>
#include <quasiloc/sim/world_builder.h>
#include <random>

namespace quasiloc::sim
{
namespace
{
using Rng = std::mt19937_64;
using Eigen::Vector2f;
using Eigen::Vector3f;

/** The rooms of one side: widths drawn around the mean until the corridor's length is used up. */
void addSide(const FloorOptions& o, int side, double hw, Rng& rng, std::vector<FloorRoom>& rooms)
{
    std::uniform_real_distribution<double> u01(0, 1);
    const double L = o.corridor_length_m, w_mean = o.room_width_m;
    double x = 0;
    while (x < L - 1e-9)
    {
        double w = w_mean * (0.75 + 0.5 * u01(rng));
        if (L - (x + w) < 0.75 * w_mean) w = L - x;  // the last room takes the rest
        FloorRoom r;
        r.side = side;
        const double y0 = side > 0 ? hw : -hw - o.room_depth_m;
        r.box = Eigen::AlignedBox2d(Eigen::Vector2d(x, y0), Eigen::Vector2d(x + w, y0 + o.room_depth_m));
        const double margin = 0.3 + 0.5 * o.door_width_m;
        r.door_x = x + margin + u01(rng) * std::max(0.0, w - 2 * margin);
        rooms.push_back(r);
        x += w;
    }
}

class FloorMeshBuilder
{
   public:
    FloorMeshBuilder(const FloorLayout& layout, float cell, Mesh& mesh) : l_(layout), cell_(cell), mesh_(mesh) {}

    /** A wall along x at y, from x0 to x1, z0 to z1; texture continues along u_offset. */
    void wallAlongX(double x0, double x1, double y, double z0, double z1, uint16_t mat)
    {
        if (x1 - x0 < 1e-3 || z1 - z0 < 1e-3) return;
        mesh_.addQuad(Vector3f(float(x0), float(y), float(z0)), Vector3f(float(x1 - x0), 0, 0),
                      Vector3f(0, 0, float(z1 - z0)), mat, cell_, Vector2f(float(x0), float(z0)));
    }
    void wallAlongY(double y0, double y1, double x, double z0, double z1, uint16_t mat)
    {
        if (y1 - y0 < 1e-3 || z1 - z0 < 1e-3) return;
        mesh_.addQuad(Vector3f(float(x), float(y0), float(z0)), Vector3f(0, float(y1 - y0), 0),
                      Vector3f(0, 0, float(z1 - z0)), mat, cell_, Vector2f(float(y0), float(z0)));
    }
    void horizontal(const Eigen::AlignedBox2d& b, double z, uint16_t mat)
    {
        const Eigen::Vector2d s = b.sizes();
        mesh_.addQuad(Vector3f(float(b.min().x()), float(b.min().y()), float(z)), Vector3f(float(s.x()), 0, 0),
                      Vector3f(0, float(s.y()), 0), mat, cell_, b.min().cast<float>());
    }

    /** The corridor wall of one side with its doors (openings up to door_height, a lintel above). */
    void corridorWall(int side)
    {
        const double y = side * l_.corridor_half_width, hd = 0.5 * l_.door_width;
        std::vector<double> doors;
        for (const FloorRoom& r : l_.rooms)
            if (r.side == side) doors.push_back(r.door_x);
        std::sort(doors.begin(), doors.end());
        double x = 0;
        for (double d : doors)
        {
            wallAlongX(x, d - hd, y, 0, l_.ceiling, kWallPlaster);
            wallAlongX(d - hd, d + hd, y, l_.door_height, l_.ceiling, kWallPlaster);
            x = d + hd;
        }
        wallAlongX(x, l_.corridor_length, y, 0, l_.ceiling, kWallPlaster);
    }

   private:
    const FloorLayout& l_;
    float cell_;
    Mesh& mesh_;
};

void addShell(const FloorLayout& l, float cell, Rng& rng, Mesh& mesh)
{
    FloorMeshBuilder b(l, cell, mesh);
    const double L = l.corridor_length, hw = l.corridor_half_width;
    const double y_lo = l.extent.min().y(), y_hi = l.extent.max().y(), H = l.ceiling;
    b.horizontal(Eigen::AlignedBox2d(Eigen::Vector2d(0, -hw), Eigen::Vector2d(L, hw)), 0, kConcrete);
    b.horizontal(Eigen::AlignedBox2d(Eigen::Vector2d(0, y_lo), Eigen::Vector2d(L, y_hi)), H, kCeilingPanels);
    b.corridorWall(+1);
    b.corridorWall(-1);
    b.wallAlongX(0, L, y_lo, 0, H, kConcrete);
    b.wallAlongX(0, L, y_hi, 0, H, kConcrete);
    b.wallAlongY(y_lo, y_hi, 0, 0, H, kConcrete);
    b.wallAlongY(y_lo, y_hi, L, 0, H, kConcrete);
    const uint16_t room_walls[] = {kWallPlaster, kWoodPanel, kConcrete, kCurtain};
    std::uniform_int_distribution<int> pick(0, 3);
    for (const FloorRoom& r : l.rooms)
    {
        b.horizontal(r.box, 0, kFloorCarpet);
        // Partition walls on both ends (the shared ones twice: coincident quads of one material look the same).
        b.wallAlongY(r.box.min().y(), r.box.max().y(), r.box.min().x(), 0, H, room_walls[pick(rng)]);
        b.wallAlongY(r.box.min().y(), r.box.max().y(), r.box.max().x(), 0, H, room_walls[pick(rng)]);
    }
}

/** An axis-aligned piece of furniture against one of the room's walls, or false when it would block the door. */
bool makeFurniture(const FloorLayout& l, const FloorRoom& r, float cell, Rng& rng, Mesh& piece,
                   Eigen::AlignedBox2d& footprint)
{
    std::uniform_real_distribution<float> u01(0.f, 1.f);
    const int kind = static_cast<int>(u01(rng) * 3) % 3;
    Vector3f size;  // along the wall, away from the wall, height
    uint16_t mat = kWoodPanel;
    if (kind == 0)
        size = Vector3f(1.2f + 0.4f * u01(rng), 0.7f + 0.1f * u01(rng), 0.75f);  // table
    else if (kind == 1)
        size = Vector3f(0.8f + 0.4f * u01(rng), 0.35f + 0.1f * u01(rng), 1.6f + 0.4f * u01(rng));  // shelf
    else
    {
        size = Vector3f(0.4f + 0.4f * u01(rng), 0.4f + 0.4f * u01(rng), 0.3f + 0.4f * u01(rng));  // boxes
        mat = kCardboard;
    }
    const int wall = static_cast<int>(u01(rng) * 4) % 4;  // 0: y min, 1: y max, 2: x min, 3: x max
    const Eigen::Vector2d lo = r.box.min(), hi = r.box.max();
    const bool along_x = wall < 2;
    const double len = along_x ? hi.x() - lo.x() : hi.y() - lo.y();
    if (len < size.x() + 0.2) return false;
    const double s = 0.1 + u01(rng) * (len - size.x() - 0.2) + 0.5 * size.x();
    Eigen::Vector2d c;
    Eigen::Vector2d half;
    if (along_x)
    {
        const double y = wall == 0 ? lo.y() + 0.5 * size.y() + 0.02 : hi.y() - 0.5 * size.y() - 0.02;
        c = Eigen::Vector2d(lo.x() + s, y);
        half = Eigen::Vector2d(0.5 * size.x(), 0.5 * size.y());
    }
    else
    {
        const double x = wall == 2 ? lo.x() + 0.5 * size.y() + 0.02 : hi.x() - 0.5 * size.y() - 0.02;
        c = Eigen::Vector2d(x, lo.y() + s);
        half = Eigen::Vector2d(0.5 * size.y(), 0.5 * size.x());
    }
    footprint = Eigen::AlignedBox2d(c - half, c + half);
    // Nothing within a metre of the door, on either side of the corridor wall.
    const double door_y = r.side * l.corridor_half_width;
    const Eigen::AlignedBox2d door(Eigen::Vector2d(r.door_x - 0.5 * l.door_width - 0.3, door_y - 1.2),
                                   Eigen::Vector2d(r.door_x + 0.5 * l.door_width + 0.3, door_y + 1.2));
    if (door.intersects(footprint)) return false;
    const Vector3f box_size = along_x ? size : Vector3f(size.y(), size.x(), size.z());
    const Vector3f centre(float(c.x()), float(c.y()), 0.5f * size.z());
    piece.addBox(centre, Eigen::Matrix3f::Identity(), box_size, mat, cell, Vector2f(u01(rng) * 5, u01(rng) * 5));
    if (kind == 0 && u01(rng) < 0.5f)  // something on the table
        piece.addBox(centre + Vector3f(0, 0, 0.5f * size.z() + 0.15f), Eigen::Matrix3f::Identity(),
                     Vector3f(0.4f, 0.3f, 0.3f), kCardboard, cell, Vector2f(u01(rng) * 5, u01(rng) * 5));
    return true;
}

/** A poster 1 cm off a wall along x (y = wall_y, facing `inward` = +1/-1) or along y, between a and b. */
void makePoster(bool along_x, double fixed, int inward, double a, double b, double ceiling, Rng& rng, float cell,
                Mesh& piece)
{
    std::uniform_real_distribution<float> u01(0.f, 1.f);
    const float w = 0.5f + 0.7f * u01(rng), h = 0.5f + 0.5f * u01(rng);
    const float z = 0.8f + u01(rng) * std::max(0.1f, float(ceiling) - 1.3f - h);
    const float s = float(a) + u01(rng) * std::max(0.f, float(b - a) - w);
    const float off = float(fixed) + 0.01f * inward;
    const uint16_t mat = u01(rng) < 0.75f ? kPoster : kCheckerBoard;
    const Vector2f uv(u01(rng) * 5, u01(rng) * 5);
    if (along_x)
        piece.addQuad(Vector3f(s, off, z), Vector3f(w, 0, 0), Vector3f(0, 0, h), mat, cell, uv);
    else
        piece.addQuad(Vector3f(off, s, z), Vector3f(0, w, 0), Vector3f(0, 0, h), mat, cell, uv);
}

void addClutter(const FloorLayout& l, const WorldOptions& o, const ClearanceGrid& grid, Rng& rng, Mesh& mesh,
                WorldStats& st)
{
    const float cell = float(o.max_cell_m), clear = float(o.clearance_m);
    std::uniform_real_distribution<double> u01(0, 1);
    auto place = [&](const Mesh& piece) { return placeIfClear(piece, grid, clear, mesh, st); };
    for (const FloorRoom& r : l.rooms)
    {
        std::vector<Eigen::AlignedBox2d> taken;
        for (int placed = 0, attempt = 0; placed < o.floor.furniture_per_room && attempt < 30; ++attempt)
        {
            Mesh piece;
            Eigen::AlignedBox2d fp;
            if (!makeFurniture(l, r, cell, rng, piece, fp)) continue;
            const bool overlaps =
                std::any_of(taken.begin(), taken.end(), [&](const auto& b) { return b.intersects(fp); });
            if (!overlaps && place(piece))
            {
                taken.push_back(fp);
                ++placed;
            }
        }
        for (int p = 0; p < o.floor.posters_per_room; ++p)
        {
            Mesh piece;
            const int wall = static_cast<int>(u01(rng) * 3) % 3;  // far wall or one of the partitions
            const Eigen::Vector2d lo = r.box.min(), hi = r.box.max();
            if (wall == 0)
                makePoster(true, r.side > 0 ? hi.y() : lo.y(), -r.side, lo.x() + 0.2, hi.x() - 0.2, l.ceiling, rng,
                           cell, piece);
            else
                makePoster(false, wall == 1 ? lo.x() : hi.x(), wall == 1 ? 1 : -1, lo.y() + 0.2, hi.y() - 0.2,
                           l.ceiling, rng, cell, piece);
            place(piece);
        }
    }
    for (int p = 0; p < o.floor.corridor_posters; ++p)
    {
        const int side = u01(rng) < 0.5 ? 1 : -1;
        const double x = u01(rng) * (l.corridor_length - 1.5);
        const bool at_door = std::any_of(l.rooms.begin(), l.rooms.end(), [&](const FloorRoom& r) {
            return r.side == side && x < r.door_x + 0.5 * l.door_width + 0.1 &&
                   x + 1.3 > r.door_x - 0.5 * l.door_width - 0.1;
        });
        if (at_door) continue;
        Mesh piece;
        makePoster(true, side * l.corridor_half_width, -side, x, x + 1.3, l.ceiling, rng, cell, piece);
        place(piece);
    }
}

void addLights(const FloorLayout& l, const WorldOptions& o, World& w)
{
    const float z = float(l.ceiling - 0.3), intensity = float(o.light_intensity);
    for (const FloorRoom& r : l.rooms)
        for (int k = 1; k <= 2; ++k)
        {
            PointLight p;
            p.position = Vector3f(float(r.box.min().x() + r.box.sizes().x() * k / 3.0), float(r.box.center().y()), z);
            p.intensity = intensity;
            w.lights.push_back(p);
        }
    const int n = std::max(1, static_cast<int>(std::round(l.corridor_length / 4.0)));
    for (int k = 0; k < n; ++k)
    {
        PointLight p;
        p.position = Vector3f(float(l.corridor_length * (k + 0.5) / n), 0.f, z);
        p.intensity = intensity;
        w.lights.push_back(p);
    }
}
}  // namespace

bool FloorLayout::isFree(const Eigen::Vector2d& p, double margin) const
{
    if (p.x() >= margin && p.x() <= corridor_length - margin && std::abs(p.y()) <= corridor_half_width - margin)
        return true;
    return std::any_of(rooms.begin(), rooms.end(), [&](const FloorRoom& r) {
        return p.x() >= r.box.min().x() + margin && p.x() <= r.box.max().x() - margin &&
               p.y() >= r.box.min().y() + margin && p.y() <= r.box.max().y() - margin;
    });
}

FloorLayout makeFloorLayout(const FloorOptions& o, uint64_t seed, const std::string& input)
{
    core::require(o.corridor_length_m >= 1.25 * o.room_width_m, input + " floor_corridor_length_m",
                  "must be at least 1.25 x floor_room_width_m (one room per side)");
    core::require(o.door_width_m + 0.6 <= 0.75 * o.room_width_m, input + " floor_door_width_m",
                  "must leave 0.3 m of wall each side in the narrowest room (0.75 x floor_room_width_m)");
    core::require(o.ceiling_m > 2.2, input + " floor_ceiling_m", "must be above the doors (2.1 m)");
    Rng rng(seed * 0x2545F4914F6CDD1Dull + 0x5851F42D4C957F2Dull);
    FloorLayout l;
    l.corridor_length = o.corridor_length_m;
    l.corridor_half_width = 0.5 * o.corridor_width_m;
    l.ceiling = o.ceiling_m;
    l.door_width = o.door_width_m;
    addSide(o, +1, l.corridor_half_width, rng, l.rooms);
    addSide(o, -1, l.corridor_half_width, rng, l.rooms);
    const double y = l.corridor_half_width + o.room_depth_m;
    l.extent = Eigen::AlignedBox3d(Eigen::Vector3d(0, -y, 0), Eigen::Vector3d(o.corridor_length_m, y, o.ceiling_m));
    return l;
}

World buildFloorWorld(const WorldOptions& o, const FloorLayout& l, uint64_t seed,
                      const std::vector<Eigen::Vector3f>& keep_clear, WorldStats* stats_out)
{
    Rng rng = worldRng(seed);
    World w = startWorld(o, seed, "floor");
    WorldStats st;
    w.room = l.extent.cast<float>();
    const ClearanceGrid grid(keep_clear, 0.5f);
    addShell(l, static_cast<float>(o.max_cell_m), rng, w.mesh);
    addClutter(l, o, grid, rng, w.mesh, st);
    addLights(l, o, w);
    finishWorld(w, grid, o.shadow_map_px, st, stats_out);
    return w;
}

}  // namespace quasiloc::sim
