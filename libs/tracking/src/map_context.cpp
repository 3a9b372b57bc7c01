#include <quasiloc/core/error.h>
#include <quasiloc/tracking/map_context.h>

namespace quasiloc::tracking
{
MapContext::MapContext(const std::string& map_file, const quasi::QuasiOptions& quasi)
    : MapContext(map::LidarMap::load(map_file), quasi, map_file)
{
}

MapContext::MapContext(map::LidarMap map, const quasi::QuasiOptions& quasi, const std::string& name)
    : map_(std::move(map)), name_(name), quasi_(quasi)
{
    renderer_ = std::make_unique<quasi::QuasiRenderer>(map_, quasi_);
}

quasi::QuasiRenderer& MapContext::searchRenderer()
{
    if (!search_renderer_)
        search_renderer_ = std::make_unique<quasi::QuasiRenderer>(map_, renderer_->sharedVisibilityIndex(), quasi_);
    return *search_renderer_;
}

std::shared_ptr<const map::DistanceField> MapContext::distanceField(const reloc::GeometricLocalizationOptions& o)
{
    if (!field_) field_ = reloc::GeometricLocalizer::buildField(map_, o, name_);
    // The layout may differ: a dense and a sparse field hold the same values.
    core::require(float(o.field_voxel_m) == field_->voxelSize() && float(o.field_max_distance_m) == field_->maxDistance(),
                  name_, "the distance field was built with other field_voxel_m / field_max_distance_m");
    return field_;
}

}  // namespace quasiloc::tracking
