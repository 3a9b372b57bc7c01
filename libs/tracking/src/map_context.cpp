#include <quasiloc/core/error.h>
#include <quasiloc/tracking/map_context.h>

#include <chrono>

namespace quasiloc::tracking
{
namespace
{
using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

map::LidarMap loadTimed(const std::string& map_file, double& seconds)
{
    const auto t0 = Clock::now();
    map::LidarMap map = map::LidarMap::load(map_file);
    seconds = secondsSince(t0);
    return map;
}
}  // namespace

MapContext::MapContext(const std::string& map_file, const quasi::QuasiOptions& quasi)
    : map_(loadTimed(map_file, figures_.load_s)), name_(map_file), quasi_(quasi)
{
    buildRenderer();
}

MapContext::MapContext(map::LidarMap map, const quasi::QuasiOptions& quasi, const std::string& name)
    : map_(std::move(map)), name_(name), quasi_(quasi)
{
    buildRenderer();
}

void MapContext::buildRenderer()
{
    const auto t0 = Clock::now();
    renderer_ = std::make_unique<quasi::QuasiRenderer>(map_, quasi_);
    figures_.points = map_.size();
    figures_.index_s = secondsSince(t0);
}

quasi::QuasiRenderer& MapContext::searchRenderer()
{
    if (!search_renderer_)
        search_renderer_ = std::make_unique<quasi::QuasiRenderer>(map_, renderer_->sharedVisibilityIndex(), quasi_);
    return *search_renderer_;
}

std::shared_ptr<const map::DistanceField> MapContext::distanceField(const reloc::GeometricLocalizationOptions& o)
{
    if (!field_)
    {
        const auto t0 = Clock::now();
        field_ = reloc::GeometricLocalizer::buildField(map_, o, name_);
        figures_.field_s = secondsSince(t0);
        figures_.field_mb = double(field_->memoryBytes()) / 1048576.0;
        figures_.field_sparse = field_->sparse();
        figures_.field_streamed = field_->streamed();
    }
    // The layout may differ: a dense and a sparse field hold the same values.
    core::require(
        float(o.field_voxel_m) == field_->voxelSize() && float(o.field_max_distance_m) == field_->maxDistance(), name_,
        "the distance field was built with other field_voxel_m / field_max_distance_m");
    return field_;
}

}  // namespace quasiloc::tracking
