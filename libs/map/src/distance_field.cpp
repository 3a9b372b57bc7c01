// DistanceField: exact squared Euclidean distance transform, one axis at a time (distance_field.h).
#include <algorithm>
#include <cmath>
#include <limits>
#include <quasiloc/core/error.h>
#include <quasiloc/map/distance_field.h>

#include "distance_field_detail.h"
#include "distance_field_streamed.h"
#include <sstream>

namespace quasiloc::map
{
using detail::kFar;

void DistanceFieldOptions::check(const std::string& input) const
{
    core::require(voxel_m > 0 && std::isfinite(voxel_m), input, "distance field voxel_m must be > 0");
    core::require(margin_m >= 0 && std::isfinite(margin_m), input, "distance field margin_m must be >= 0");
    core::require(max_distance_m > 0 && std::isfinite(max_distance_m), input,
                  "distance field max_distance_m must be > 0");
    core::require(max_voxels > 0, input, "distance field max_voxels must be > 0");
    core::require(memory_budget_mb > 0 && std::isfinite(memory_budget_mb), input,
                  "distance field memory_budget_mb must be > 0");
    core::require(focus_radius_m >= 0 && std::isfinite(focus_radius_m), input,
                  "distance field focus_radius_m must be >= 0");
}

DistanceField DistanceField::build(const LidarMap& map, const DistanceFieldOptions& o, const std::string& input)
{
    o.check(input);
    core::require(!map.empty(), input, "the map is empty: no distance field");
    const MapBounds b = map.bounds();
    DistanceField f;
    f.voxel_ = float(o.voxel_m);
    f.max_distance_ = float(o.max_distance_m);
    f.step_ = f.max_distance_ / 65535.f;
    // Voxel centres on the world lattice of multiples of the voxel: a place's values do not depend on how far the
    // map extends elsewhere (a room alone and the same room inside a campus share their voxels).
    const Eigen::Vector3d lo = ((b.min.cast<double>().array() - o.margin_m) / o.voxel_m).floor() * o.voxel_m;
    f.origin_ = lo.cast<float>();
    const Eigen::Vector3f extent = b.max + Eigen::Vector3f::Constant(float(o.margin_m)) - f.origin_;
    const Eigen::Vector3d n = (extent.cast<double>() / o.voxel_m).array().ceil() + 1;
    core::require(n.maxCoeff() < 1e6, input, "a distance field over 1e6 voxels along an axis: use a larger voxel");
    f.nx_ = int(n.x()), f.ny_ = int(n.y()), f.nz_ = int(n.z());
    const double voxels = n.x() * n.y() * n.z();
    if (o.layout == DistanceFieldLayout::Streamed) return buildStreamed(map, std::move(f), o, input);
    const bool sparse = o.layout == DistanceFieldLayout::Sparse ||
                        (o.layout == DistanceFieldLayout::Auto && voxels > double(o.dense_max_voxels));
    return sparse ? buildSparse(map, std::move(f)) : buildDense(map, std::move(f), input, o);
}

DistanceField DistanceField::buildDense(const LidarMap& map, DistanceField f, const std::string& input,
                                        const DistanceFieldOptions& o)
{
    const double voxels = double(f.nx_) * double(f.ny_) * double(f.nz_);
    if (voxels > double(o.max_voxels))
    {
        std::ostringstream s;
        s << "a dense distance field of " << f.nx_ << " x " << f.ny_ << " x " << f.nz_ << " voxels of " << f.voxel_
          << " m exceeds max_voxels = " << o.max_voxels << ": use a larger voxel, or layout = sparse";
        throw core::InputError(input, s.str());
    }
    std::vector<float> d(size_t(voxels), kFar);
    for (size_t i = 0; i < map.size(); ++i)
    {
        const Eigen::Vector3f g = (map.point(i) - f.origin_) / f.voxel_;
        const int x = int(std::lround(g.x())), y = int(std::lround(g.y())), z = int(std::lround(g.z()));
        d[f.index(x, y, z)] = 0.f;
    }
    const detail::Box grid{Eigen::Vector3i::Zero(), Eigen::Vector3i(f.nx_, f.ny_, f.nz_)};
    detail::transform(d, grid.size());
    // Voxels within one voxel (Chebyshev) of an occupied one take the exact distance to the points of their
    // 3 x 3 x 3 neighbourhood (detail::nearestInNeighbourhood says why).
    std::vector<float> near(d.size(), kFar);
    for (size_t n = 0; n < map.size(); ++n)
        detail::nearestInNeighbourhood((map.point(n) - f.origin_) / f.voxel_, grid, near);
    f.d_.resize(d.size());
    for (size_t v = 0; v < d.size(); ++v)
        f.d_[v] = f.quantize(detail::finalDistance(near[v], d[v], f.voxel_, f.max_distance_));
    return f;
}

DistanceField DistanceField::buildStreamed(const LidarMap& map, DistanceField f, const DistanceFieldOptions& o,
                                           const std::string& input)
{
    f.bx_ = (f.nx_ + kBrick - 1) / kBrick, f.by_ = (f.ny_ + kBrick - 1) / kBrick, f.bz_ = (f.nz_ + kBrick - 1) / kBrick;
    const detail::TileGrid grid(f.origin_, f.voxel_, f.max_distance_, Eigen::Vector3i(f.nx_, f.ny_, f.nz_));
    f.streamed_ = std::make_shared<detail::StreamedTiles>(map, grid, o, input);
    return f;
}

float DistanceField::streamedVoxel(int i, int j, int k) const { return value(streamed_->voxel(i, j, k)); }

void DistanceField::focus(const Eigen::Vector3f& p_world) const
{
    if (streamed_) streamed_->focus(p_world);
}

void DistanceField::waitForFocus() const
{
    if (streamed_) streamed_->waitForFocus();
}

size_t DistanceField::writeAllTiles() const
{
    core::require(streamed_ != nullptr, "DistanceField::writeAllTiles", "only a streamed field has tiles to write");
    return streamed_->writeAll();
}

size_t DistanceField::memoryBytes() const
{
    if (streamed_) return streamed_->memoryBytes();
    return (d_.size() + bricks_.size() * size_t(kBrickVoxels)) * sizeof(uint16_t) + brick_of_.size() * sizeof(int);
}

size_t DistanceField::allocatedBricks() const { return streamed_ ? streamed_->residentBricks() : bricks_.size(); }

DistanceField::StreamStats DistanceField::streamStats() const { return streamed_ ? streamed_->stats() : StreamStats{}; }

float DistanceField::distance(const Eigen::Vector3f& p_world) const { return sample(p_world, nullptr); }

float DistanceField::distance(const Eigen::Vector3f& p_world, Eigen::Vector3f& gradient) const
{
    return sample(p_world, &gradient);
}

float DistanceField::sample(const Eigen::Vector3f& p_world, Eigen::Vector3f* gradient) const
{
    // The value alone (the global start's scoring: most of its lookups) skips the gradient's arithmetic; the value
    // is the same expression either way.
    if (gradient) gradient->setZero();
    const Eigen::Vector3f g = (p_world - origin_) / voxel_;
    if (!(g.x() >= 0 && g.y() >= 0 && g.z() >= 0 && g.x() < float(nx_ - 1) && g.y() < float(ny_ - 1) &&
          g.z() < float(nz_ - 1)))
        return max_distance_;
    const int i = int(g.x()), j = int(g.y()), k = int(g.z());
    const float a = g.x() - float(i), b = g.y() - float(j), c = g.z() - float(k);
    float d000, d100, d010, d110, d001, d101, d011, d111;
    if (streamed_)
    {
        uint16_t c[8];
        streamed_->cell(i, j, k, c);
        d000 = value(c[0]), d100 = value(c[1]), d010 = value(c[2]), d110 = value(c[3]);
        d001 = value(c[4]), d101 = value(c[5]), d011 = value(c[6]), d111 = value(c[7]);
    }
    else if (!sparse_)
    {
        const size_t o = index(i, j, k), dy = size_t(nx_), dz = size_t(nx_) * size_t(ny_);
        d000 = value(d_[o]), d100 = value(d_[o + 1]), d010 = value(d_[o + dy]), d110 = value(d_[o + dy + 1]);
        d001 = value(d_[o + dz]), d101 = value(d_[o + dz + 1]), d011 = value(d_[o + dz + dy]);
        d111 = value(d_[o + dz + dy + 1]);
    }
    else
    {
        d000 = sparseVoxel(i, j, k), d100 = sparseVoxel(i + 1, j, k), d010 = sparseVoxel(i, j + 1, k);
        d110 = sparseVoxel(i + 1, j + 1, k), d001 = sparseVoxel(i, j, k + 1), d101 = sparseVoxel(i + 1, j, k + 1);
        d011 = sparseVoxel(i, j + 1, k + 1), d111 = sparseVoxel(i + 1, j + 1, k + 1);
    }
    // Bilinear in (x, y) on the two z layers, then linear in z.
    const float l0 = (1 - b) * ((1 - a) * d000 + a * d100) + b * ((1 - a) * d010 + a * d110);
    const float l1 = (1 - b) * ((1 - a) * d001 + a * d101) + b * ((1 - a) * d011 + a * d111);
    if (gradient)
    {
        const float dx0 = (1 - b) * (d100 - d000) + b * (d110 - d010),
                    dx1 = (1 - b) * (d101 - d001) + b * (d111 - d011);
        const float dy0 = (1 - a) * (d010 - d000) + a * (d110 - d100),
                    dy1 = (1 - a) * (d011 - d001) + a * (d111 - d101);
        *gradient = Eigen::Vector3f((1 - c) * dx0 + c * dx1, (1 - c) * dy0 + c * dy1, l1 - l0) / voxel_;
    }
    return (1 - c) * l0 + c * l1;
}

}  // namespace quasiloc::map
