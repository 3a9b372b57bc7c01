#pragma once
// The LiDAR map and what is built from it, built once and shared by the tracker, the loss check and the
// relocalization: the map, its visibility index (inside the renderers), the distance field of its surfaces and
// the quasi-image renderers, one per thread that renders.
#include <memory>
#include <quasiloc/map/distance_field.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/quasi/quasi_options.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <quasiloc/reloc/geometric_localizer.h>
#include <string>

namespace quasiloc::tracking
{
/** What loading the map and building from it took (a large map: tens of seconds, GBs). */
struct MapBuildFigures
{
    size_t points = 0;
    double load_s = 0;   ///< reading the map file
    double index_s = 0;  ///< the visibility index and the tracker's renderer
    double field_s = 0;  ///< the distance field (0 until built)
    double field_mb = 0;
    bool field_sparse = false, field_streamed = false;
};

class MapContext
{
   public:
    /** Loads the map file (InputError naming it) and builds the tracker's renderer (and with it the visibility
     *  index). */
    MapContext(const std::string& map_file, const quasi::QuasiOptions& quasi);
    /** The same from a map already in memory; `name` names it in errors. */
    MapContext(map::LidarMap map, const quasi::QuasiOptions& quasi, const std::string& name);

    const map::LidarMap& map() const { return map_; }
    const std::string& name() const { return name_; }

    /** The tracking thread's renderer. */
    quasi::QuasiRenderer& renderer() { return *renderer_; }
    /** A second renderer, for the relocalization's thread (the same visibility index); made on first use. */
    quasi::QuasiRenderer& searchRenderer();

    /** The distance field of the map's surfaces with `o`'s voxel and truncation, built on first use (about 0.7 s
     *  for a room): the stereo surface factor, the loss check and the relocalization read the same field. A later
     *  call with other field options is an InputError. */
    std::shared_ptr<const map::DistanceField> distanceField(const reloc::GeometricLocalizationOptions& o);

    const MapBuildFigures& figures() const { return figures_; }

   private:
    void buildRenderer();

    MapBuildFigures figures_;  // first: the map's load time is recorded while map_ is initialised
    map::LidarMap map_;
    std::string name_;
    quasi::QuasiOptions quasi_;
    std::unique_ptr<quasi::QuasiRenderer> renderer_, search_renderer_;
    std::shared_ptr<const map::DistanceField> field_;
};

}  // namespace quasiloc::tracking
