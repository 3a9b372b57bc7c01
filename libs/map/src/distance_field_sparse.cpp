// The sparse DistanceField (distance_field.h): only the bricks within the truncation of a map point are stored.
// Bricks are transformed a tile at a time (kTile^3 bricks) on a buffer that adds an apron of `reach` voxels on every
// side: a distance up to the truncation comes from an occupied voxel at most `reach` voxels away, which the apron
// holds, so every stored value is the dense grid's to the bit.
#include <algorithm>
#include <cmath>
#include <quasiloc/map/distance_field.h>
#include <unordered_map>

#include "distance_field_detail.h"

namespace quasiloc::map
{
namespace
{
using detail::kFar;
constexpr int kTile = 8;  ///< bricks per tile side: a 128^3-voxel core (the apron costs 1.8x its volume)

struct Box
{
    Eigen::Vector3i lo, hi;  ///< voxel bounds, hi exclusive
    Eigen::Vector3i size() const { return hi - lo; }
    size_t index(int i, int j, int k) const
    {
        const Eigen::Vector3i s = size();
        return (size_t(k - lo.z()) * size_t(s.y()) + size_t(j - lo.y())) * size_t(s.x()) + size_t(i - lo.x());
    }
    bool contains(int i, int j, int k) const
    {
        return i >= lo.x() && j >= lo.y() && k >= lo.z() && i < hi.x() && j < hi.y() && k < hi.z();
    }
};

/** The 3-pass exact squared distance transform of a box's buffer (occupied: 0, else kFar). */
void transform(std::vector<float>& d, const Eigen::Vector3i& n)
{
    const int longest = n.maxCoeff();
    std::vector<int> v(static_cast<size_t>(longest));
    std::vector<float> z(static_cast<size_t>(longest) + 1), tmp(static_cast<size_t>(longest));
    const size_t sy = size_t(n.x()), sz = size_t(n.x()) * size_t(n.y());
    auto at = [&](int i, int j, int k) { return &d[size_t(k) * sz + size_t(j) * sy + size_t(i)]; };
    for (int k = 0; k < n.z(); ++k)
        for (int j = 0; j < n.y(); ++j) detail::squaredDistance1d(at(0, j, k), n.x(), 1, v, z, tmp);
    for (int k = 0; k < n.z(); ++k)
        for (int i = 0; i < n.x(); ++i) detail::squaredDistance1d(at(i, 0, k), n.y(), sy, v, z, tmp);
    for (int j = 0; j < n.y(); ++j)
        for (int i = 0; i < n.x(); ++i) detail::squaredDistance1d(at(i, j, 0), n.z(), sz, v, z, tmp);
}
}  // namespace

DistanceField DistanceField::buildSparse(const LidarMap& map, DistanceField f)
{
    f.sparse_ = true;
    f.bx_ = (f.nx_ + kBrick - 1) / kBrick, f.by_ = (f.ny_ + kBrick - 1) / kBrick, f.bz_ = (f.nz_ + kBrick - 1) / kBrick;
    const Eigen::Vector3i grid(f.nx_, f.ny_, f.nz_), bricks(f.bx_, f.by_, f.bz_);
    const auto brickIndex = [&](const Eigen::Vector3i& b) {
        return (size_t(b.z()) * size_t(f.by_) + size_t(b.y())) * size_t(f.bx_) + size_t(b.x());
    };
    // The map's points by the brick of their voxel, with the continuous voxel coordinates the dense build uses.
    std::unordered_map<size_t, std::vector<Eigen::Vector3f>> points_of_brick;
    for (size_t n = 0; n < map.size(); ++n)
    {
        const Eigen::Vector3f g = (map.point(n) - f.origin_) / f.voxel_;
        const Eigen::Vector3i v(int(std::lround(g.x())), int(std::lround(g.y())), int(std::lround(g.z())));
        points_of_brick[brickIndex(v / kBrick)].push_back(g);
    }
    // A voxel farther than `reach` from every occupied voxel is at the truncation.
    const int reach = int(std::ceil(f.max_distance_ / f.voxel_)) + 1;
    const int brick_reach = (reach + kBrick - 1) / kBrick;  // reach >= 1 also covers the refinement's neighbours
    f.brick_of_.assign(size_t(f.bx_) * size_t(f.by_) * size_t(f.bz_), -1);
    std::vector<char> needed(f.brick_of_.size(), 0);
    for (const auto& [b, pts] : points_of_brick)
    {
        const Eigen::Vector3i c(int(b % size_t(f.bx_)), int(b / size_t(f.bx_) % size_t(f.by_)),
                                int(b / (size_t(f.bx_) * size_t(f.by_))));
        const Eigen::Vector3i lo = (c.array() - brick_reach).max(0), hi = (c.array() + brick_reach).min(bricks.array() - 1);
        for (int z = lo.z(); z <= hi.z(); ++z)
            for (int y = lo.y(); y <= hi.y(); ++y)
                for (int x = lo.x(); x <= hi.x(); ++x) needed[brickIndex({x, y, z})] = 1;
    }
    std::vector<float> buffer, near;
    for (int tz = 0; tz < f.bz_; tz += kTile)
        for (int ty = 0; ty < f.by_; ty += kTile)
            for (int tx = 0; tx < f.bx_; tx += kTile)
            {
                const Eigen::Vector3i t0(tx, ty, tz), t1 = (t0.array() + kTile).min(bricks.array());
                bool any = false;
                for (int z = t0.z(); z < t1.z() && !any; ++z)
                    for (int y = t0.y(); y < t1.y() && !any; ++y)
                        for (int x = t0.x(); x < t1.x() && !any; ++x) any = needed[brickIndex({x, y, z})];
                if (!any) continue;
                const Box core{t0 * kBrick, (t1 * kBrick).cwiseMin(grid)};
                const Box padded{(core.lo.array() - reach).max(0), (core.hi.array() + reach).min(grid.array())};
                // The occupied voxels of the padded box, and the points within one voxel of the core.
                buffer.assign(size_t(padded.size().prod()), kFar);
                near.assign(size_t(core.size().prod()), kFar);
                const Eigen::Vector3i b0 = (padded.lo / kBrick), b1 = ((padded.hi.array() - 1) / kBrick).matrix();
                for (int z = b0.z(); z <= b1.z(); ++z)
                    for (int y = b0.y(); y <= b1.y(); ++y)
                        for (int x = b0.x(); x <= b1.x(); ++x)
                        {
                            const auto it = points_of_brick.find(brickIndex({x, y, z}));
                            if (it == points_of_brick.end()) continue;
                            for (const Eigen::Vector3f& g : it->second)
                            {
                                const int vx = int(std::lround(g.x())), vy = int(std::lround(g.y())),
                                          vz = int(std::lround(g.z()));
                                if (padded.contains(vx, vy, vz)) buffer[padded.index(vx, vy, vz)] = 0.f;
                                for (int k = std::max(core.lo.z(), vz - 1); k <= std::min(core.hi.z() - 1, vz + 1); ++k)
                                    for (int j = std::max(core.lo.y(), vy - 1); j <= std::min(core.hi.y() - 1, vy + 1); ++j)
                                        for (int i = std::max(core.lo.x(), vx - 1); i <= std::min(core.hi.x() - 1, vx + 1); ++i)
                                        {
                                            const float d2 = (Eigen::Vector3f(float(i), float(j), float(k)) - g).squaredNorm();
                                            float& best = near[core.index(i, j, k)];
                                            best = std::min(best, d2);
                                        }
                            }
                        }
                transform(buffer, padded.size());
                // Each needed brick of the tile: its final values, kept when any is below the truncation.
                for (int z = t0.z(); z < t1.z(); ++z)
                    for (int y = t0.y(); y < t1.y(); ++y)
                        for (int x = t0.x(); x < t1.x(); ++x)
                        {
                            if (!needed[brickIndex({x, y, z})]) continue;
                            std::vector<float> values(size_t(kBrickVoxels), f.max_distance_);
                            bool below = false;
                            for (int k = 0; k < kBrick; ++k)
                                for (int j = 0; j < kBrick; ++j)
                                    for (int i = 0; i < kBrick; ++i)
                                    {
                                        const int gi = x * kBrick + i, gj = y * kBrick + j, gk = z * kBrick + k;
                                        if (!core.contains(gi, gj, gk)) continue;  // beyond the grid
                                        const float nd = near[core.index(gi, gj, gk)];
                                        const float d2 = nd < kFar ? nd : buffer[padded.index(gi, gj, gk)];
                                        const float d = std::min(f.max_distance_, std::sqrt(d2) * f.voxel_);
                                        values[size_t((k * kBrick + j) * kBrick + i)] = d;
                                        below = below || d < f.max_distance_;
                                    }
                            if (!below) continue;
                            f.brick_of_[brickIndex({x, y, z})] = int(f.bricks_.size());
                            f.bricks_.push_back(std::move(values));
                        }
            }
    return f;
}

}  // namespace quasiloc::map
