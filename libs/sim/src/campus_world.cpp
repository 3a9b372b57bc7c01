// The outdoor campus (campus_world.h): streets, blocks, buildings with windows, trees, parked cars, people, the sun.
#include <algorithm>
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/sim/campus_world.h>
#include <quasiloc/sim/clearance_grid.h>
#include <quasiloc/sim/world_builder.h>
#include <random>

namespace quasiloc::sim
{
namespace
{
using Rng = std::mt19937_64;
using Eigen::Vector2d;
using Eigen::Vector2f;
using Eigen::Vector3f;

constexpr float kPaintZ = 0.005f;  ///< markings lie this far above the asphalt (no z-fighting)

Vector3f at(double x, double y, double z) { return Vector3f(float(x), float(y), float(z)); }

/** A horizontal rectangle at height z, texture in world metres. */
void horizontal(Mesh& mesh, const Eigen::AlignedBox2d& b, double z, uint16_t mat, float cell)
{
    const Vector2d s = b.sizes();
    if (s.x() < 1e-3 || s.y() < 1e-3) return;
    mesh.addQuad(at(b.min().x(), b.min().y(), z), at(s.x(), 0, 0), at(0, s.y(), 0), mat, cell, b.min().cast<float>());
}

/** The carriageways, intersections and margin at z = 0, the blocks as raised slabs with kerbs. */
void addGround(const CampusLayout& l, float cell, Mesh& mesh)
{
    // Breakpoints of the ground along one axis: the margin, then street / block intervals alternately.
    std::vector<double> cuts = {l.extent.min().x()};
    for (int k = 0; k <= l.blocks; ++k)
    {
        cuts.push_back(l.street(k) - l.street_half);
        cuts.push_back(l.street(k) + l.street_half);
    }
    cuts.push_back(l.extent.max().x());
    const double shift = l.extent.min().y() - l.extent.min().x();  // the campus is square: same cuts along y
    const size_t n = cuts.size() - 1;
    for (size_t i = 0; i < n; ++i)
        for (size_t j = 0; j < n; ++j)
        {
            const Eigen::AlignedBox2d r(Vector2d(cuts[i], cuts[j] + shift), Vector2d(cuts[i + 1], cuts[j + 1] + shift));
            const bool street_x = i % 2 == 1, street_y = j % 2 == 1;  // odd intervals are streets
            const bool margin = i == 0 || j == 0 || i + 1 == n || j + 1 == n;
            if (street_x || street_y)
                horizontal(mesh, r, 0, kAsphalt, cell);
            else if (margin)
                horizontal(mesh, r, 0, kConcrete, cell);
            else
            {
                horizontal(mesh, r, l.kerb, kConcrete, cell);
                const Vector2d lo = r.min(), hi = r.max(), s = r.sizes();
                const float k = float(l.kerb);
                mesh.addQuad(at(lo.x(), lo.y(), 0), at(s.x(), 0, 0), at(0, 0, k), kConcrete, cell);
                mesh.addQuad(at(lo.x(), hi.y(), 0), at(s.x(), 0, 0), at(0, 0, k), kConcrete, cell);
                mesh.addQuad(at(lo.x(), lo.y(), 0), at(0, s.y(), 0), at(0, 0, k), kConcrete, cell);
                mesh.addQuad(at(hi.x(), lo.y(), 0), at(0, s.y(), 0), at(0, 0, k), kConcrete, cell);
            }
        }
    // The boundary wall.
    const Vector2d lo = l.extent.min(), s = l.extent.sizes();
    const float h = 2.5f;
    mesh.addQuad(at(lo.x(), lo.y(), 0), at(s.x(), 0, 0), at(0, 0, h), kConcrete, cell);
    mesh.addQuad(at(lo.x(), lo.y() + s.y(), 0), at(s.x(), 0, 0), at(0, 0, h), kConcrete, cell);
    mesh.addQuad(at(lo.x(), lo.y(), 0), at(0, s.y(), 0), at(0, 0, h), kConcrete, cell);
    mesh.addQuad(at(lo.x() + s.x(), lo.y(), 0), at(0, s.y(), 0), at(0, 0, h), kConcrete, cell);
}

/** A paint rectangle centred at c, `along` metres in direction dir (unit, horizontal), `across` wide. */
void paint(Mesh& mesh, const Vector2d& c, const Vector2d& dir, double along, double across, float cell)
{
    const Vector2d side(-dir.y(), dir.x());
    const Vector2d o = c - 0.5 * along * dir - 0.5 * across * side;
    mesh.addQuad(at(o.x(), o.y(), kPaintZ), at(along * dir.x(), along * dir.y(), 0),
                 at(across * side.x(), across * side.y(), 0), kRoadPaint, cell, o.cast<float>());
}

/** Dashed centre lines between intersections and zebra crossings on every approach. */
void addMarkings(const CampusLayout& l, float cell, Mesh& mesh)
{
    const double dash = 3, gap = 3, zebra_depth = 3, stripe = 0.5;
    for (int axis = 0; axis < 2; ++axis)  // 0: streets along x (constant y), 1: along y
        for (int k = 0; k <= l.blocks; ++k)
            for (int b = 0; b < l.blocks; ++b)
            {
                const double s0 = l.street(b) + l.street_half, s1 = l.street(b + 1) - l.street_half;
                const Vector2d dir = axis == 0 ? Vector2d(1, 0) : Vector2d(0, 1);
                auto point = [&](double s, double offset) {
                    return axis == 0 ? Vector2d(s, l.street(k) + offset) : Vector2d(l.street(k) + offset, s);
                };
                // Zebra crossings: stripes along the street, side by side across it, at both ends.
                for (double start : {s0 + 0.5, s1 - 0.5 - zebra_depth})
                    for (double off = -l.street_half + 0.6; off + stripe <= l.street_half - 0.4; off += 2 * stripe)
                        paint(mesh, point(start + 0.5 * zebra_depth, off + 0.5 * stripe), dir, zebra_depth, stripe,
                              cell);
                for (double s = s0 + zebra_depth + 2; s + dash <= s1 - zebra_depth - 2; s += dash + gap)
                    paint(mesh, point(s + 0.5 * dash, 0), dir, dash, 0.15, cell);
            }
}

/** A building: four facades with rows of windows (glass 3 cm off the wall) and a flat roof. */
void addBuilding(const Eigen::AlignedBox2d& fp, double base_z, double height, const CampusOptions& o, Rng& rng,
                 float cell, Mesh& mesh)
{
    const uint16_t walls[] = {kWallPlaster, kConcrete, kWoodPanel, kConcrete};
    std::uniform_real_distribution<double> u01(0, 1);
    const uint16_t wall = walls[size_t(u01(rng) * 4) % 4];
    const Vector2d lo = fp.min(), hi = fp.max();
    const Vector2d corners[4] = {lo, Vector2d(hi.x(), lo.y()), hi, Vector2d(lo.x(), hi.y())};
    const double win_w = 1.2 + 0.4 * u01(rng), win_h = 1.4 + 0.4 * u01(rng), spacing = win_w + 1.4 + 1.0 * u01(rng);
    double u_along = 0;
    for (int f = 0; f < 4; ++f)
    {
        const Vector2d a = corners[f], b = corners[(f + 1) % 4];
        const double len = (b - a).norm();
        const Vector2d dir = (b - a) / len, out(dir.y(), -dir.x());  // corners run counter-clockwise
        mesh.addQuad(at(a.x(), a.y(), base_z), at(b.x() - a.x(), b.y() - a.y(), 0), at(0, 0, height), wall, cell,
                     Vector2f(float(u_along), 0));
        u_along += len;
        const int columns = int((len - 1.0) / spacing);
        const double first = 0.5 * (len - (columns - 1) * spacing);
        for (double z = base_z + 1.0; z + win_h <= base_z + height - 0.8; z += o.storey_m)
            for (int c = 0; c < columns; ++c)
            {
                const Vector2d p = a + (first + c * spacing - 0.5 * win_w) * dir + 0.03 * out;
                mesh.addQuad(at(p.x(), p.y(), z), at(win_w * dir.x(), win_w * dir.y(), 0), at(0, 0, win_h), kGlass,
                             cell, Vector2f(float(u01(rng) * 5), float(u01(rng) * 5)));
            }
    }
    horizontal(mesh, fp, base_z + height, kConcrete, cell);
}

/** One to three buildings side by side on the block's inner area (inside the sidewalks), 2-4 m apart. */
void addBuildings(const CampusLayout& l, const CampusOptions& o, Rng& rng, float cell, Mesh& mesh, WorldStats& st)
{
    std::uniform_real_distribution<double> u01(0, 1);
    for (int i = 0; i < l.blocks; ++i)
        for (int j = 0; j < l.blocks; ++j)
        {
            const Eigen::AlignedBox2d b = l.block(i, j);
            const Vector2d lo = b.min() + Vector2d::Constant(l.sidewalk), hi = b.max() - Vector2d::Constant(l.sidewalk);
            const int count = 1 + int(u01(rng) * 3) % 3;
            const bool split_x = u01(rng) < 0.5;
            const int axis = split_x ? 0 : 1;
            const double span = hi[axis] - lo[axis], gap = 2 + 2 * u01(rng);
            const double w = (span - (count - 1) * gap) / count;
            if (w < 6) continue;
            for (int c = 0; c < count; ++c)
            {
                Vector2d a = lo, z = hi;
                a[axis] = lo[axis] + c * (w + gap);
                z[axis] = a[axis] + w;
                const double h =
                    o.building_min_height_m + u01(rng) * (o.building_max_height_m - o.building_min_height_m);
                addBuilding(Eigen::AlignedBox2d(a, z), l.kerb, h, o, rng, cell, mesh);
                ++st.objects_placed;
            }
        }
}

/** A place along one side of a block: distance s along the kerb and the outward normal of that side. */
struct KerbPlace
{
    Vector2d p, along, out;  ///< a point on the kerb, the kerb's direction, towards the street
};

KerbPlace kerbPlace(const Eigen::AlignedBox2d& b, int side, double f)
{
    const Vector2d lo = b.min(), hi = b.max(), s = b.sizes();
    switch (side)
    {
        case 0: return {Vector2d(lo.x() + f * s.x(), lo.y()), Vector2d(1, 0), Vector2d(0, -1)};
        case 1: return {Vector2d(hi.x(), lo.y() + f * s.y()), Vector2d(0, 1), Vector2d(1, 0)};
        case 2: return {Vector2d(lo.x() + f * s.x(), hi.y()), Vector2d(1, 0), Vector2d(0, 1)};
        default: return {Vector2d(lo.x(), lo.y() + f * s.y()), Vector2d(0, 1), Vector2d(-1, 0)};
    }
}

Eigen::Matrix3f yawOf(const Vector2d& dir)
{
    return Eigen::AngleAxisf(float(std::atan2(dir.y(), dir.x())), Vector3f::UnitZ()).toRotationMatrix();
}

void addStreetFurniture(const CampusLayout& l, const CampusOptions& o, const ClearanceGrid& grid, float clear,
                        float cell, Rng& rng, Mesh& mesh, WorldStats& st)
{
    std::uniform_real_distribution<double> u01(0, 1);
    auto place = [&](const Mesh& piece) { return placeIfClear(piece, grid, clear, mesh, st); };
    const double kerb_z = l.kerb;
    for (int i = 0; i < l.blocks; ++i)
        for (int j = 0; j < l.blocks; ++j)
        {
            const Eigen::AlignedBox2d b = l.block(i, j);
            for (int side = 0; side < 4; ++side)
            {
                for (int t = 0; t < o.trees_per_side; ++t)  // evenly spaced, 1 m in from the kerb
                {
                    const KerbPlace k = kerbPlace(b, side, (t + 0.5) / o.trees_per_side);
                    const Vector2d c = k.p - 1.0 * k.out;
                    const double trunk_h = 2.5 + u01(rng), crown_r = 1.2 + 0.8 * u01(rng);
                    Mesh tree;
                    tree.addCylinder(at(c.x(), c.y(), kerb_z), 0.15f, float(trunk_h + 0.5), 8, kBark, cell);
                    tree.addCylinder(at(c.x(), c.y(), kerb_z + trunk_h), float(crown_r), float(2.5 + u01(rng)), 10,
                                     kFoliage, cell);
                    place(tree);
                }
                for (int p = 0; p < o.people_per_side; ++p)  // standing on the sidewalk
                {
                    const KerbPlace k = kerbPlace(b, side, 0.1 + 0.8 * u01(rng));
                    const Vector2d c = k.p - (0.8 + (l.sidewalk - 1.4) * u01(rng)) * k.out;
                    Mesh person;
                    person.addCylinder(at(c.x(), c.y(), kerb_z), 0.22f, float(1.6 + 0.25 * u01(rng)), 10,
                                       kPersonClothes, cell);
                    place(person);
                }
                // Parked cars in the parking strip along the kerb, in slots clear of the zebra crossings.
                const double len = (side % 2 == 0 ? b.sizes().x() : b.sizes().y()) - 2 * 6.0;
                const int slots = std::max(0, int(len / 6.0));
                std::vector<int> free_slots(static_cast<size_t>(slots));
                for (int s = 0; s < slots; ++s) free_slots[size_t(s)] = s;
                std::shuffle(free_slots.begin(), free_slots.end(), rng);
                for (int c = 0; c < std::min(slots, o.parked_cars_per_side); ++c)
                {
                    const double f =
                        (6.0 + (free_slots[size_t(c)] + 0.5) * 6.0) / (side % 2 == 0 ? b.sizes().x() : b.sizes().y());
                    const KerbPlace k = kerbPlace(b, side, f);
                    const Vector2d centre = k.p + 1.15 * k.out;
                    const Eigen::Matrix3f R = yawOf(k.along);
                    Mesh car;
                    car.addBox(at(centre.x(), centre.y(), 0.65), R, Vector3f(4.4f, 1.8f, 0.8f), kCarPaint, cell,
                               Vector2f(float(u01(rng) * 5), float(u01(rng) * 5)));
                    car.addBox(at(centre.x(), centre.y(), 1.32), R, Vector3f(2.3f, 1.6f, 0.55f), kGlass, cell);
                    place(car);
                }
            }
        }
}
}  // namespace

Eigen::AlignedBox2d CampusLayout::block(int i, int j) const
{
    return Eigen::AlignedBox2d(Vector2d(street(i) + street_half, street(j) + street_half),
                               Vector2d(street(i + 1) - street_half, street(j + 1) - street_half));
}

bool CampusLayout::onCarriageway(const Vector2d& p, double margin) const
{
    const double hi = street(blocks) + street_half - margin, lo = -street_half + margin;
    if (p.x() < lo || p.y() < lo || p.x() > hi || p.y() > hi) return false;
    auto near_street = [&](double v) {
        const double k = std::round(v / pitch);
        return std::abs(v - k * pitch) <= street_half - margin;
    };
    return near_street(p.x()) || near_street(p.y());
}

CampusLayout makeCampusLayout(const CampusOptions& o, const std::string& input)
{
    core::require(o.block_size_m >= o.street_width_m + 2 * o.sidewalk_width_m + 10, input + " campus_block_size_m",
                  "must leave a block of 10 m or more inside its streets and sidewalks");
    core::require(o.building_max_height_m >= o.building_min_height_m, input + " campus_building_max_height_m",
                  "must be >= campus_building_min_height_m");
    CampusLayout l;
    l.blocks = o.blocks_per_side;
    l.pitch = o.block_size_m;
    l.street_half = 0.5 * o.street_width_m;
    l.sidewalk = o.sidewalk_width_m;
    const double m = l.street_half + o.margin_m;
    l.extent = Eigen::AlignedBox2d(Vector2d::Constant(-m), Vector2d::Constant(l.street(l.blocks) + m));
    return l;
}

World buildCampusWorld(const WorldOptions& o, const CampusLayout& l, uint64_t seed,
                       const std::vector<Eigen::Vector3f>& keep_clear, WorldStats* stats_out)
{
    Rng rng = worldRng(seed);
    World w = startWorld(o, seed, "campus");
    WorldStats st;
    const float top = float(o.campus.building_max_height_m + 1);
    w.room = Eigen::AlignedBox3f(at(l.extent.min().x(), l.extent.min().y(), 0),
                                 at(l.extent.max().x(), l.extent.max().y(), top));
    const float cell = float(o.max_cell_m);
    addGround(l, cell, w.mesh);
    addMarkings(l, cell, w.mesh);
    addBuildings(l, o.campus, rng, cell, w.mesh, st);
    const ClearanceGrid grid(keep_clear, 0.5f);
    addStreetFurniture(l, o.campus, grid, float(o.clearance_m), cell, rng, w.mesh, st);
    // The sun: far above and to one side, its intensity such that light_intensity is the irradiance it gives.
    const Eigen::Vector3f centre = w.room.center();
    const float side = float(l.extent.sizes().maxCoeff());
    PointLight sun;
    sun.position = centre + Eigen::Vector3f(0.4f * side + 300.f, 0.25f * side + 200.f, 1.5f * side + 600.f);
    sun.intensity = float(o.light_intensity) * (sun.position - centre).squaredNorm();
    w.lights.push_back(sun);
    finishWorld(w, grid, o.shadow_map_px, st, stats_out);
    return w;
}

std::vector<Eigen::Vector3f> campusMappingTour(const CampusLayout& l)
{
    std::vector<Eigen::Vector3f> tour;
    const double end = l.street(l.blocks);
    for (int k = 0; k <= l.blocks; ++k)  // streets along x, serpentine; the connections run along x = 0 or end
    {
        const bool forward = k % 2 == 0;
        tour.push_back(at(forward ? 0 : end, l.street(k), 0));
        tour.push_back(at(forward ? end : 0, l.street(k), 0));
    }
    const bool at_end = l.blocks % 2 == 0;  // where the last street along x ended
    for (int k = 0; k <= l.blocks; ++k)     // streets along y, from the corner reached
    {
        const int c = at_end ? l.blocks - k : k;
        const bool up = k % 2 == 1;
        tour.push_back(at(l.street(c), up ? 0 : end, 0));
        tour.push_back(at(l.street(c), up ? end : 0, 0));
    }
    return tour;
}

}  // namespace quasiloc::sim
