#pragma once
// NearPoints: the map points near a set of query points, on a hash grid, for exact nearest-neighbour queries within a
// radius (the geometric localizer's point-to-point polish). The points are gathered from the visibility index's blocks
// around the query, so building one costs what the query covers, not what the map holds: a k-d tree of a whole
// 100 M-point map took 25 s and about 1.4 GB, for a polish that looks 10 cm around 2000 points.
#include <Eigen/Core>
#include <quasiloc/map/visibility_index.h>
#include <unordered_map>
#include <vector>

namespace quasiloc::reloc
{
class NearPoints
{
   public:
    /** Keeps every map point within reach_m of one of `points_world`; the grid's cells are cell_m wide. */
    NearPoints(const map::VisibilityIndex& index, const std::vector<Eigen::Vector3f>& points_world, float reach_m,
               float cell_m);

    /** The nearest kept point to q closer than radius_m (<= cell_m); false when there is none. Exact (the same
     *  distance as a search of the whole map) when q lies within reach_m - radius_m of the point it stands for. */
    bool nearest(const Eigen::Vector3f& q, float radius_m, Eigen::Vector3f& point, float& d2) const;

    size_t size() const { return points_.size(); }

   private:
    uint64_t key(const Eigen::Vector3f& p) const;

    float cell_;
    std::vector<Eigen::Vector3f> points_;                                ///< grouped by cell
    std::unordered_map<uint64_t, std::pair<uint32_t, uint32_t>> cells_;  ///< cell -> [begin, end) in points_
};

}  // namespace quasiloc::reloc
