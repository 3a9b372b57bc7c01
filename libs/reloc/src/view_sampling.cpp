#include <quasiloc/core/error.h>
#include <quasiloc/core/ini_read.h>
#include <quasiloc/reloc/view_sampling.h>

#include <mrpt/math/CMatrixFixed.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_map>
#include <unordered_set>
#include <cstdint>

namespace quasiloc::reloc
{
namespace
{

/** Occupied voxels of the map (hash set), plus the lowest occupied z of every column. */
class OccupancyGrid
{
   public:
    OccupancyGrid(const map::LidarMap& map, double voxel_m) : voxel_(voxel_m)
    {
        occupied_.reserve(map.size() / 4);
        const float *xs = map.xs(), *ys = map.ys(), *zs = map.zs();
        for (size_t i = 0; i < map.size(); ++i)
        {
            const int ix = cell(xs[i]), iy = cell(ys[i]), iz = cell(zs[i]);
            occupied_.insert(key(ix, iy, iz));
            auto [it, inserted] = floor_.try_emplace(key2(ix, iy), zs[i]);
            if (!inserted) it->second = std::min(it->second, zs[i]);
        }
    }
    int cell(double v) const { return int(std::floor(v / voxel_)); }
    bool occupied(int ix, int iy, int iz) const { return occupied_.count(key(ix, iy, iz)) != 0; }
    bool occupiedAt(double x, double y, double z) const { return occupied(cell(x), cell(y), cell(z)); }
    /** Lowest map z in the column of (x, y) or its 8 neighbours (a single empty column is a sampling gap). */
    bool floorZ(double x, double y, double& z) const
    {
        const int ix = cell(x), iy = cell(y);
        bool found = false;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
                if (auto it = floor_.find(key2(ix + dx, iy + dy)); it != floor_.end())
                {
                    z = found ? std::min(z, double(it->second)) : double(it->second);
                    found = true;
                }
        return found;
    }
    /** Any occupied voxel whose centre lies within r of p (conservative by half a voxel diagonal). */
    bool occupiedWithin(double x, double y, double z, double r) const
    {
        const int n = int(std::ceil(r / voxel_)) + 1;
        const int cx = cell(x), cy = cell(y), cz = cell(z);
        const double reach = r + 0.87 * voxel_;
        for (int dz = -n; dz <= n; ++dz)
            for (int dy = -n; dy <= n; ++dy)
                for (int dx = -n; dx <= n; ++dx)
                {
                    const double vx = (cx + dx + 0.5) * voxel_ - x, vy = (cy + dy + 0.5) * voxel_ - y,
                                 vz = (cz + dz + 0.5) * voxel_ - z;
                    if (vx * vx + vy * vy + vz * vz <= reach * reach && occupied(cx + dx, cy + dy, cz + dz))
                        return true;
                }
        return false;
    }
    /** Marches from p along unit d in half-voxel steps; true when an occupied voxel is met within max_m. */
    bool rayHits(double x, double y, double z, double dx, double dy, double dz, double max_m) const
    {
        for (double s = 0.5 * voxel_; s <= max_m; s += 0.5 * voxel_)
            if (occupiedAt(x + s * dx, y + s * dy, z + s * dz)) return true;
        return false;
    }

   private:
    static uint64_t key(int ix, int iy, int iz)
    {
        const auto u = [](int v) { return uint64_t(uint32_t(v + (1 << 20)) & 0x1FFFFFu); };
        return (u(ix) << 42) | (u(iy) << 21) | u(iz);
    }
    static uint64_t key2(int ix, int iy) { return (uint64_t(uint32_t(ix)) << 32) | uint32_t(iy); }
    double voxel_;
    std::unordered_set<uint64_t> occupied_;
    std::unordered_map<uint64_t, float> floor_;
};
}  // namespace

void ViewSamplingOptions::declare(core::OptionTable& t)
{
    using core::Range;
    t.add("grid_spacing_m", grid_spacing_m, "m", Range::above(0), "spacing of the horizontal position grid");
    t.add("heights_m", heights_m, "m", Range::any(), "camera heights above the floor below the position");
    t.add("num_headings", num_headings, "", Range::between(1, 360),
          "headings evenly spread over 360 deg (the first along +x)");
    t.add("pitches_deg", pitches_deg, "deg", Range::strictlyBetween(-89, 89),
          "camera pitch(es), positive = looking up");
    t.add("clearance_m", clearance_m, "m", Range::atLeast(0), "no map point within this distance of a viewpoint");
    t.add("voxel_m", voxel_m, "m", Range::above(0),
          "occupancy grid of the map used for the clearance / floor / enclosure tests");
    t.add("require_enclosed", require_enclosed,
          "indoors: rays in 8 horizontal directions, and straight up where the map has a ceiling, must hit the map "
          "within max_ray_m");
    t.add("ceiling_min_share", ceiling_min_share, "", Range::between(0, 1),
          "require_enclosed: the ray up must hit too when at least this share of the positions enclosed by walls "
          "have a ceiling above them (0: always; a map built from a LiDAR that saw the ceiling in part has less)");
    t.add("max_ray_m", max_ray_m, "m", Range::above(0), "enclosure ray length");
    t.add("region", region, "m", Range::any(), "optional [xmin ymin xmax ymax] (world): sample only there");
    t.add("margin_m", margin_m, "m", Range::atLeast(0), "distance kept from the map's horizontal bounds");
}

void ViewSamplingOptions::check(const std::string& input) const
{
    const auto key = [&](const char* k) { return input + ": " + core::iniKeyName("ViewSampling", k); };
    checkRanges(input, "ViewSampling");
    core::require(!heights_m.empty(), key("heights_m"), "needs at least one height");
    core::require(!pitches_deg.empty(), key("pitches_deg"), "needs at least one pitch");
    core::require(region.empty() || (region.size() == 4 && region[0] < region[2] && region[1] < region[3]),
                  key("region"), "must be empty or [xmin ymin xmax ymax] with xmin < xmax, ymin < ymax");
}

mrpt::poses::CPose3D viewPose(double x, double y, double z, double heading_rad, double pitch_rad)
{
    // Columns of R_world_cam are the camera axes in the world: x right, y down, z forward.
    const Eigen::Vector3d forward(std::cos(pitch_rad) * std::cos(heading_rad),
                                  std::cos(pitch_rad) * std::sin(heading_rad), std::sin(pitch_rad));
    const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
    const Eigen::Vector3d down = forward.cross(right);
    mrpt::math::CMatrixDouble33 R;
    for (int r = 0; r < 3; ++r)
    {
        R(r, 0) = right[r];
        R(r, 1) = down[r];
        R(r, 2) = forward[r];
    }
    mrpt::math::CVectorFixedDouble<3> t;
    t[0] = x;
    t[1] = y;
    t[2] = z;
    return mrpt::poses::CPose3D(R, t);
}

std::vector<mrpt::poses::CPose3D> sampleViewpoints(const map::LidarMap& map, const ViewSamplingOptions& options,
                                                   ViewSamplingStats* stats)
{
    options.check("ViewSampling");
    core::require(!map.empty(), "the LiDAR map", "is empty: no viewpoints can be sampled");
    ViewSamplingStats st;
    const OccupancyGrid grid(map, options.voxel_m);
    const map::MapBounds b = map.bounds();
    double x0 = b.min.x() + options.margin_m, y0 = b.min.y() + options.margin_m;
    double x1 = b.max.x() - options.margin_m, y1 = b.max.y() - options.margin_m;
    if (options.region.size() == 4)
    {
        x0 = std::max(x0, options.region[0]);
        y0 = std::max(y0, options.region[1]);
        x1 = std::min(x1, options.region[2]);
        y1 = std::min(y1, options.region[3]);
    }
    constexpr double kPi = 3.14159265358979323846;
    std::vector<mrpt::poses::CPose3D> views;
    // The grid is the world lattice of multiples of the spacing: the positions in a place do not depend on how far
    // the map extends elsewhere (a room alone and the same room inside a campus get the same candidates).
    const double s = options.grid_spacing_m;
    const int64_t i0 = int64_t(std::ceil(x0 / s - 1e-9)), i1 = int64_t(std::floor(x1 / s + 1e-9));
    const int64_t j0 = int64_t(std::ceil(y0 / s - 1e-9)), j1 = int64_t(std::floor(y1 / s + 1e-9));
    struct Position
    {
        double x, y, z;
        bool ceiling;  ///< the ray straight up hits the map
    };
    std::vector<Position> kept;
    size_t with_ceiling = 0;
    for (int64_t j = j0; j <= j1; ++j)
        for (int64_t i = i0; i <= i1; ++i)
        {
            const double x = double(i) * s, y = double(j) * s;
            ++st.grid_positions;
            double floor_z = 0;
            if (!grid.floorZ(x, y, floor_z))
            {
                ++st.no_floor;
                continue;
            }
            for (double h : options.heights_m)
            {
                const double z = floor_z + h;
                if (grid.occupiedWithin(x, y, z, options.clearance_m))
                {
                    ++st.not_clear;
                    continue;
                }
                bool walls = true;
                for (int k = 0; options.require_enclosed && walls && k < 8; ++k)
                    walls = grid.rayHits(x, y, z, std::cos(k * kPi / 4), std::sin(k * kPi / 4), 0, options.max_ray_m);
                if (!walls)
                {
                    ++st.not_enclosed;
                    continue;
                }
                const bool ceiling = options.require_enclosed && grid.rayHits(x, y, z, 0, 0, 1, options.max_ray_m);
                with_ceiling += ceiling ? 1 : 0;
                kept.push_back({x, y, z, ceiling});
            }
        }
    // A ceiling is asked for where the map has one over most of its enclosed positions; a map whose mapping LiDAR
    // saw the ceiling only in part is enclosed by its walls alone.
    st.ceiling_share = kept.empty() ? 0.0 : double(with_ceiling) / double(kept.size());
    st.ceiling_required = options.require_enclosed && st.ceiling_share >= options.ceiling_min_share;
    for (const Position& p : kept)
    {
        if (st.ceiling_required && !p.ceiling)
        {
            ++st.not_enclosed;
            continue;
        }
        ++st.positions;
        for (int k = 0; k < options.num_headings; ++k)
            for (double pitch : options.pitches_deg)
                views.push_back(viewPose(p.x, p.y, p.z, 2 * kPi * k / options.num_headings, pitch * kPi / 180));
    }
    st.views = views.size();
    if (stats) *stats = st;
    return views;
}

}  // namespace quasiloc::reloc
