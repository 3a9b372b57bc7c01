#pragma once
// VisibilityIndex: the renderer's input. The map's points are bucketed into cubic blocks and stored
// block by block (contiguous, structure of arrays), so a query returns the few contiguous ranges whose
// blocks intersect the camera frustum within a range limit. Every stored point keeps the index of the
// LidarMap point it is (provenance survives the reordering).
#include <mrpt/poses/CPose3D.h>

#include <cstdint>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/map/lidar_map.h>
#include <vector>

namespace quasiloc::map
{
class VisibilityIndex
{
   public:
    struct Options
    {
        double block_size_m = 1.0;
    };
    /** A contiguous run [begin, end) of the index's point arrays. */
    struct Range
    {
        uint32_t begin = 0, end = 0;
    };

    VisibilityIndex() = default;
    VisibilityIndex(const LidarMap& map, const Options& options);

    /** Ranges of all points possibly visible from T_world_cam with `camera` up to max_range_m (a
     *  conservative superset: whole blocks that intersect the frustum). Clears `out` first. */
    void query(const mrpt::poses::CPose3D& T_world_cam, const core::CameraModel& camera, double max_range_m,
               std::vector<Range>& out) const;

    size_t size() const { return map_index_.size(); }
    size_t numBlocks() const { return blocks_.size(); }
    // Point arrays in block order.
    const float* xs() const { return x_.data(); }
    const float* ys() const { return y_.data(); }
    const float* zs() const { return z_.data(); }
    const float* reflectivities() const { return refl_.data(); }
    /** mapIndex()[k] = index in the LidarMap of the k-th stored point. */
    const uint32_t* mapIndex() const { return map_index_.data(); }

   private:
    struct Block
    {
        Eigen::Vector3f min, max;  ///< tight bounds of the block's points
        Range range;
    };
    Options options_;
    std::vector<Block> blocks_;
    std::vector<float> x_, y_, z_, refl_;
    std::vector<uint32_t> map_index_;
};

}  // namespace quasiloc::map
