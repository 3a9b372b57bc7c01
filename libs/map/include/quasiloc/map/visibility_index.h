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
        /// Blocks are grouped into cubic super-blocks of this many blocks per edge: a query first culls
        /// super-blocks, then the blocks of the surviving ones (1 = a flat list of blocks).
        int superblock_blocks = 8;
    };
    /** A contiguous run [begin, end) of the index's point arrays. */
    struct Range
    {
        uint32_t begin = 0, end = 0;
    };

    VisibilityIndex() = default;
    VisibilityIndex(const LidarMap& map, const Options& options);

    /** Ranges of all points possibly visible from T_world_cam with `camera` up to max_range_m (a
     *  conservative superset: whole blocks that intersect the frustum). Clears `out` first.
     *  max_range_m limits the depth (camera z), like a renderer's far plane. Adjacent blocks are merged
     *  into one range. Points that only a non-monotonic (folding) distortion polynomial would bring into
     *  the image from outside the lens's field of view are not considered. */
    void query(const mrpt::poses::CPose3D& T_world_cam, const core::CameraModel& camera, double max_range_m,
               std::vector<Range>& out) const;

    /** The camera's viewing cone in the camera frame: half-spaces n . p_cam <= 0 (planes through the
     *  optical centre) enclosing the rays of every image pixel, built from the unprojected border of the
     *  image (so distortion is respected), plus the axis-aligned bounds of that region on the z = 1 plane. */
    struct ViewCone
    {
        std::vector<Eigen::Vector3d> side_normals;
        Eigen::Vector2d xn_min{0, 0}, xn_max{0, 0};
        bool bounded = false;  ///< false: the border could not be unprojected; the cone is the half-space z >= 0
    };
    static ViewCone viewCone(const core::CameraModel& camera);
    /** Same as query() with a precomputed cone (saves the border unprojection per query). */
    void query(const mrpt::poses::CPose3D& T_world_cam, const ViewCone& cone, double max_range_m,
               std::vector<Range>& out) const;

    /** Ranges of all points of the blocks whose bounds intersect the world box [lo, hi] (a superset of the points
     *  inside it). Clears `out` first. Its work grows with the box, not with the map. */
    void queryBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, std::vector<Range>& out) const;

    /** Number of points in `ranges`. */
    static size_t countPoints(const std::vector<Range>& ranges);

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
    struct Superblock
    {
        Eigen::Vector3f min, max;  ///< tight bounds of its blocks
        uint32_t first_block = 0, end_block = 0;
        uint64_t key = 0;  ///< super-block cell (x slowest, z fastest): the order they are stored in
    };
    /** Calls visit(s) for every super-block whose cell the world box [flo, fhi] covers, in key order: the work of
     *  a query grows with its range, not with the map. */
    template <typename F>
    void forSuperblocksIn(const Eigen::Vector3d& flo, const Eigen::Vector3d& fhi, F&& visit) const;
    Options options_;
    std::vector<Block> blocks_;
    std::vector<Superblock> superblocks_;
    double inv_block_ = 1;  ///< the grid of super-block cells: 1 / block size, lowest block, cells per axis
    int64_t superblocks_per_edge_ = 1, block_lo_[3] = {0, 0, 0}, n_super_[3] = {1, 1, 1};
    std::vector<float> x_, y_, z_, refl_;
    std::vector<uint32_t> map_index_;
};

}  // namespace quasiloc::map
