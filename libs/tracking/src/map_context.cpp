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

bool MapContext::hasReflectivity() const
{
    const auto [lo, hi] = map_.reflectivityRange();
    return hi - lo > 1e-3f;
}

quasi::QuasiRenderer& MapContext::searchRenderer()
{
    if (!search_renderer_)
        search_renderer_ = std::make_unique<quasi::QuasiRenderer>(map_, renderer_->visibilityIndex(), quasi_);
    return *search_renderer_;
}

std::shared_ptr<const map::DistanceField> MapContext::distanceField(const reloc::GeometricLocalizationOptions& o)
{
    if (!field_)
    {
        field_ = reloc::GeometricLocalizer::buildField(map_, o, name_);
        field_voxel_m_ = o.field_voxel_m;
        field_max_distance_m_ = o.field_max_distance_m;
    }
    core::require(o.field_voxel_m == field_voxel_m_ && o.field_max_distance_m == field_max_distance_m_, name_,
                  "the distance field was built with other field_voxel_m / field_max_distance_m");  // layout: same values
    return field_;
}

}  // namespace quasiloc::tracking
