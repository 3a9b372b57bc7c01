#pragma once
// LidarMap: the prior LiDAR map, an mrpt::maps::CPointsMapXYZI whose intensity channel holds the
// reflectivity of every point normalised to [0, 1] (see map_import.h for the normalisation rule).
// On disk: MRPT's binary serialization of the CPointsMapXYZI (gz-compressed stream), so MRPT tools
// (e.g. SceneViewer3D / RawLogViewer's object viewers) can open it.
#include <mrpt/maps/CPointsMapXYZI.h>

#include <Eigen/Core>
#include <string>

namespace quasiloc::map
{
struct MapBounds
{
    Eigen::Vector3f min{0, 0, 0}, max{0, 0, 0};
};

class LidarMap
{
   public:
    LidarMap();
    explicit LidarMap(mrpt::maps::CPointsMapXYZI::Ptr points);

    size_t size() const { return points_->size(); }
    bool empty() const { return size() == 0; }
    void reserve(size_t n);
    /** Appends a point; reflectivity is expected in [0, 1]. */
    void addPoint(float x, float y, float z, float reflectivity);

    const float* xs() const { return points_->getPointsBufferRef_x().data(); }
    const float* ys() const { return points_->getPointsBufferRef_y().data(); }
    const float* zs() const { return points_->getPointsBufferRef_z().data(); }
    const float* reflectivities() const { return points_->getPointsBufferRef_intensity().data(); }
    Eigen::Vector3f point(size_t i) const { return {xs()[i], ys()[i], zs()[i]}; }
    float reflectivity(size_t i) const { return reflectivities()[i]; }

    const mrpt::maps::CPointsMapXYZI& points() const { return *points_; }
    mrpt::maps::CPointsMapXYZI::Ptr pointsPtr() const { return points_; }

    MapBounds bounds() const;
    /** Reflectivity minimum and maximum. */
    std::pair<float, float> reflectivityRange() const;

    /** InputError naming `input` for an empty map, a non-finite coordinate or a reflectivity outside [0,1]. */
    void check(const std::string& input) const;

    /** Atomic write (temporary + rename). */
    void save(const std::string& path) const;
    /** InputError for a missing file, a file that is not a serialized CPointsMapXYZI, or a map failing check(). */
    static LidarMap load(const std::string& path);

    /** "N points, bounds [..]..[..] m, reflectivity [a, b]". */
    std::string summary() const;

   private:
    mrpt::maps::CPointsMapXYZI::Ptr points_;
};

}  // namespace quasiloc::map
