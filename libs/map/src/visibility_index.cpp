// VisibilityIndex: points sorted by (super-block, block), so that a block and a super-block are each one
// contiguous range; a query culls super-block then block bounding boxes against the view frustum.
#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/map/visibility_index.h>

namespace quasiloc::map
{
namespace
{
/** A world-frame half-space n . p <= offset. */
struct HalfSpace
{
    Eigen::Vector3d n;
    double offset;
};

/** True if the box [lo, hi] lies entirely outside one of the half-spaces (so no point of it is visible). */
bool boxOutside(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, const std::vector<HalfSpace>& planes)
{
    const Eigen::Vector3d c = 0.5 * (lo + hi).cast<double>();
    const Eigen::Vector3d h = 0.5 * (hi - lo).cast<double>();
    for (const HalfSpace& p : planes)
    {
        const double nearest = p.n.dot(c) - p.n.cwiseAbs().dot(h);
        // Tolerance: the bounds are floats, the caller's projections doubles; never cull on rounding.
        const double tol = 1e-6 * (1.0 + std::abs(p.offset) + p.n.cwiseAbs().dot(c.cwiseAbs()));
        if (nearest > p.offset + tol) return true;
    }
    return false;
}

bool boxesOverlap(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, const Eigen::Vector3d& flo,
                  const Eigen::Vector3d& fhi)
{
    for (int a = 0; a < 3; ++a)
        if (lo[a] > fhi[a] || hi[a] < flo[a]) return false;
    return true;
}

/** Integer block coordinates relative to the lowest block, and the grid size, for the sort key. */
struct BlockGrid
{
    double inv = 1.0;
    int64_t lo[3] = {0, 0, 0};
    int64_t n_super[3] = {1, 1, 1};
    int64_t S = 1;

    uint64_t key(float x, float y, float z) const
    {
        const float p[3] = {x, y, z};
        int64_t sup[3], loc[3];
        for (int a = 0; a < 3; ++a)
        {
            const int64_t b = static_cast<int64_t>(std::floor(p[a] * inv)) - lo[a];
            sup[a] = b / S;
            loc[a] = b % S;
        }
        const uint64_t s = static_cast<uint64_t>((sup[0] * n_super[1] + sup[1]) * n_super[2] + sup[2]);
        const uint64_t l = static_cast<uint64_t>((loc[0] * S + loc[1]) * S + loc[2]);
        return s * static_cast<uint64_t>(S * S * S) + l;
    }
    uint64_t superOf(uint64_t key) const { return key / static_cast<uint64_t>(S * S * S); }
    /** Super-block cell of world coordinate v along axis a (not clamped to the grid). */
    int64_t superCell(double v, int a) const
    {
        const double b = std::floor(v * inv) - double(lo[a]);
        return static_cast<int64_t>(std::floor(std::clamp(b, -1e15, 1e15) / double(S)));
    }
};

BlockGrid makeGrid(const LidarMap& map, const VisibilityIndex::Options& o)
{
    core::require(o.block_size_m > 0 && std::isfinite(o.block_size_m), "VisibilityIndex block_size_m", "must be > 0");
    core::require(o.superblock_blocks >= 1 && o.superblock_blocks <= 64, "VisibilityIndex superblock_blocks",
                  "must be within 1..64");
    BlockGrid g;
    g.inv = 1.0 / o.block_size_m;
    g.S = o.superblock_blocks;
    const MapBounds b = map.bounds();
    double cells = 1;
    for (int a = 0; a < 3; ++a)
    {
        g.lo[a] = static_cast<int64_t>(std::floor(b.min[a] * g.inv));
        const int64_t span = static_cast<int64_t>(std::floor(b.max[a] * g.inv)) - g.lo[a] + 1;
        g.n_super[a] = (span + g.S - 1) / g.S;
        cells *= static_cast<double>(g.n_super[a]) * static_cast<double>(g.S);
    }
    core::require(cells < 1e18, "VisibilityIndex block_size_m", "too small for the map's extent");
    return g;
}
}  // namespace

VisibilityIndex::VisibilityIndex(const LidarMap& map, const Options& options) : options_(options)
{
    const size_t n = map.size();
    core::require(n < (size_t(1) << 32), "VisibilityIndex", "more than 2^32 points");
    if (n == 0) return;
    const BlockGrid grid = makeGrid(map, options);
    inv_block_ = grid.inv;
    superblocks_per_edge_ = grid.S;
    for (int a = 0; a < 3; ++a) block_lo_[a] = grid.lo[a], n_super_[a] = grid.n_super[a];
    // Points by block key, map order within a block: a counting sort over the occupied blocks (far fewer than the
    // points), so the only temporary the size of the map is the 4-byte order (a 100 M-point map: 0.4 GB, where
    // sorting (key, index) pairs took 1.6 GB).
    std::unordered_map<uint64_t, uint32_t> count_of;
    for (size_t i = 0; i < n; ++i) ++count_of[grid.key(map.xs()[i], map.ys()[i], map.zs()[i])];
    std::vector<std::pair<uint64_t, uint32_t>> block_starts(count_of.begin(), count_of.end());
    std::sort(block_starts.begin(), block_starts.end());
    uint32_t start = 0;
    for (auto& [key, c] : block_starts) std::swap(c, start), start += c;  // count -> first position
    std::unordered_map<uint64_t, uint32_t> next(block_starts.begin(), block_starts.end());
    count_of.clear();
    std::vector<uint32_t> order(n);
    for (size_t i = 0; i < n; ++i) order[next[grid.key(map.xs()[i], map.ys()[i], map.zs()[i])]++] = uint32_t(i);
    next.clear();
    std::vector<uint64_t> keys;
    keys.reserve(block_starts.size());
    for (const auto& [key, first] : block_starts) keys.push_back(key);

    x_.resize(n);
    y_.resize(n);
    z_.resize(n);
    refl_.resize(n);
    map_index_.resize(n);
    size_t block = 0;  // keys[block]: the key of the block point k is in
    for (size_t k = 0; k < n; ++k)
    {
        const uint32_t i = order[k];
        const Eigen::Vector3f p(map.xs()[i], map.ys()[i], map.zs()[i]);
        x_[k] = p.x();
        y_[k] = p.y();
        z_[k] = p.z();
        refl_[k] = map.reflectivities()[i];
        map_index_[k] = i;
        const bool new_block = k == 0 || (block + 1 < keys.size() && k == block_starts[block + 1].second);
        if (new_block)
        {
            if (k > 0) ++block;
            if (k == 0 || grid.superOf(keys[block]) != grid.superOf(keys[block - 1]))
                superblocks_.push_back(
                    {p, p, uint32_t(blocks_.size()), uint32_t(blocks_.size()), grid.superOf(keys[block])});
            blocks_.push_back({p, p, {uint32_t(k), uint32_t(k)}});
            ++superblocks_.back().end_block;
        }
        Block& b = blocks_.back();
        b.min = b.min.cwiseMin(p);
        b.max = b.max.cwiseMax(p);
        b.range.end = uint32_t(k + 1);
        Superblock& s = superblocks_.back();
        s.min = s.min.cwiseMin(p);
        s.max = s.max.cwiseMax(p);
    }
}

VisibilityIndex::ViewCone VisibilityIndex::viewCone(const core::CameraModel& camera)
{
    ViewCone cone;
    if (camera.width <= 0 || camera.height <= 0) return cone;
    // Samples along the outer edge of the border pixels, clockwise in the image.
    constexpr int kPerSide = 32;
    const double W = camera.width - 0.5, H = camera.height - 0.5;
    const Eigen::Vector2d corners[4] = {{-0.5, -0.5}, {W, -0.5}, {W, H}, {-0.5, H}};
    auto borderPoint = [&](int side, double t, Eigen::Vector2d& out) {
        const Eigen::Vector3d r = camera.unproject((1 - t) * corners[side] + t * corners[(side + 1) % 4]);
        out = {r.x(), r.y()};
        return std::isfinite(r.x()) && std::isfinite(r.y());
    };
    std::vector<Eigen::Vector2d> xn(4 * kPerSide);
    double margin = 1e-6;
    for (int side = 0; side < 4; ++side)
        for (int k = 0; k < kPerSide; ++k)
            if (!borderPoint(side, double(k) / kPerSide, xn[side * kPerSide + k])) return cone;  // unbounded
    // Between two samples the unprojected border is a curve, not the chord: widen every support line by
    // twice the largest midpoint deviation from its chord (zero for a pinhole camera).
    for (int side = 0; side < 4; ++side)
        for (int k = 0; k < kPerSide; ++k)
        {
            const Eigen::Vector2d& a = xn[side * kPerSide + k];
            const Eigen::Vector2d& b = xn[(side * kPerSide + k + 1) % xn.size()];
            Eigen::Vector2d mid;
            if (!borderPoint(side, (k + 0.5) / kPerSide, mid)) return cone;
            const Eigen::Vector2d ab = b - a;
            const double len = ab.norm();
            const double dev =
                len > 0 ? std::abs(ab.x() * (mid - a).y() - ab.y() * (mid - a).x()) / len : (mid - a).norm();
            margin = std::max(margin, 2.0 * dev + 1e-6);
        }

    // Support lines of the sampled region in 8 directions: an octagon that contains the region.
    Eigen::Vector2d lo = xn[0], hi = xn[0];
    for (const auto& p : xn)
    {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    cone.xn_min = lo.array() - margin;
    cone.xn_max = hi.array() + margin;
    for (int k = 0; k < 8; ++k)
    {
        const double a = k * M_PI / 4;
        const Eigen::Vector2d d(std::cos(a), std::sin(a));
        double support = -1e300;
        for (const auto& p : xn) support = std::max(support, d.dot(p));
        if (k % 2 == 1)
        {
            // A diagonal line is useless when it does not cut the samples' axis-aligned box (pinhole).
            const Eigen::Vector2d corner(d.x() > 0 ? hi.x() : lo.x(), d.y() > 0 ? hi.y() : lo.y());
            if (support >= d.dot(corner) - 1e-12) continue;
        }
        support += margin;
        // d . (X/Z, Y/Z) <= support  <=>  (d.x, d.y, -support) . p_cam <= 0   for Z > 0.
        cone.side_normals.emplace_back(d.x(), d.y(), -support);
    }
    cone.bounded = true;
    return cone;
}

void VisibilityIndex::query(const mrpt::poses::CPose3D& T_world_cam, const core::CameraModel& camera,
                            double max_range_m, std::vector<Range>& out) const
{
    query(T_world_cam, viewCone(camera), max_range_m, out);
}

void VisibilityIndex::query(const mrpt::poses::CPose3D& T_world_cam, const ViewCone& cone, double max_range_m,
                            std::vector<Range>& out) const
{
    out.clear();
    if (blocks_.empty() || !(max_range_m > 0)) return;
    const Eigen::Isometry3d T = core::toIsometry(T_world_cam);
    const Eigen::Matrix3d R = T.linear();
    const Eigen::Vector3d t = T.translation();
    // Camera-frame half-spaces n_c . p_c <= o_c become n_w . p_w <= o_c + n_w . t with n_w = R n_c.
    std::vector<HalfSpace> planes;
    auto add = [&](const Eigen::Vector3d& n_c, double o_c) {
        const Eigen::Vector3d n_w = R * n_c;
        planes.push_back({n_w, o_c + n_w.dot(t)});
    };
    add({0, 0, 1}, max_range_m);  // depth <= max range
    add({0, 0, -1}, 0.0);         // in front of the camera
    for (const auto& n : cone.side_normals) add(n, 0.0);

    // World bounds of the frustum: the apex and the far rectangle that encloses the cone. An unbounded
    // cone (the half-space z >= 0) is unbounded sideways too: no bounds test then.
    Eigen::Vector3d flo = t, fhi = t;
    if (cone.bounded)
        for (int c = 0; c < 4; ++c)
        {
            const Eigen::Vector3d p_cam(c & 1 ? cone.xn_max.x() : cone.xn_min.x(),
                                        c & 2 ? cone.xn_max.y() : cone.xn_min.y(), 1.0);
            const Eigen::Vector3d p_w = T * (max_range_m * p_cam);
            flo = flo.cwiseMin(p_w);
            fhi = fhi.cwiseMax(p_w);
        }
    else
    {
        flo.setConstant(-std::numeric_limits<double>::infinity());
        fhi.setConstant(std::numeric_limits<double>::infinity());
    }
    // Rounding slack: the caller projects in double, the bounds are floats.
    flo.array() -= 1e-4 * (1.0 + max_range_m);
    fhi.array() += 1e-4 * (1.0 + max_range_m);

    const auto visit = [&](const Superblock& s) {
        if (!boxesOverlap(s.min, s.max, flo, fhi) || boxOutside(s.min, s.max, planes)) return;
        for (uint32_t b = s.first_block; b < s.end_block; ++b)
        {
            const Block& blk = blocks_[b];
            if (!boxesOverlap(blk.min, blk.max, flo, fhi) || boxOutside(blk.min, blk.max, planes)) continue;
            if (!out.empty() && out.back().end == blk.range.begin)
                out.back().end = blk.range.end;
            else
                out.push_back(blk.range);
        }
    };
    forSuperblocksIn(flo, fhi, visit);
}

template <typename F>
void VisibilityIndex::forSuperblocksIn(const Eigen::Vector3d& flo, const Eigen::Vector3d& fhi, F&& visit) const
{
    // The super-block cells the box covers, clamped to the grid. When they are fewer than the stored
    // super-blocks (a camera in a large map), only those cells are looked up; otherwise all are scanned. Both
    // visit in key order, so the ranges come out the same.
    BlockGrid grid;
    grid.inv = inv_block_;
    grid.S = superblocks_per_edge_;
    int64_t c0[3], c1[3];
    double cells = 1;
    for (int a = 0; a < 3; ++a)
    {
        grid.lo[a] = block_lo_[a];
        c0[a] = std::max<int64_t>(0, grid.superCell(flo[a], a));
        c1[a] = std::min<int64_t>(n_super_[a] - 1, grid.superCell(fhi[a], a));
        if (c1[a] < c0[a]) return;
        cells *= double(c1[a] - c0[a] + 1);
    }
    if (cells >= double(superblocks_.size()))
    {
        for (const Superblock& s : superblocks_) visit(s);
        return;
    }
    const auto keyOf = [&](int64_t x, int64_t y, int64_t z) {
        return uint64_t((x * n_super_[1] + y) * n_super_[2] + z);
    };
    const auto byKey = [](const Superblock& s, uint64_t key) { return s.key < key; };
    for (int64_t x = c0[0]; x <= c1[0]; ++x)
        for (int64_t y = c0[1]; y <= c1[1]; ++y)
        {
            const uint64_t last = keyOf(x, y, c1[2]);
            auto it = std::lower_bound(superblocks_.begin(), superblocks_.end(), keyOf(x, y, c0[2]), byKey);
            for (; it != superblocks_.end() && it->key <= last; ++it) visit(*it);
        }
}

void VisibilityIndex::queryBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, std::vector<Range>& out) const
{
    out.clear();
    if (blocks_.empty()) return;
    forSuperblocksIn(lo, hi, [&](const Superblock& s) {
        if (!boxesOverlap(s.min, s.max, lo, hi)) return;
        for (uint32_t b = s.first_block; b < s.end_block; ++b)
        {
            const Block& blk = blocks_[b];
            if (!boxesOverlap(blk.min, blk.max, lo, hi)) continue;
            if (!out.empty() && out.back().end == blk.range.begin)
                out.back().end = blk.range.end;
            else
                out.push_back(blk.range);
        }
    });
}

size_t VisibilityIndex::countPoints(const std::vector<Range>& ranges)
{
    size_t n = 0;
    for (const Range& r : ranges) n += r.end - r.begin;
    return n;
}

}  // namespace quasiloc::map
