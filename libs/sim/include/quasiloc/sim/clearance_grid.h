#pragma once
// Distance queries between a set of positions (trajectory samples) and triangles, via a uniform hash grid
// of the positions. Used to keep the simulated geometry clear of the real flight paths.
#include <Eigen/Core>
#include <quasiloc/sim/world.h>
#include <unordered_map>
#include <vector>

namespace quasiloc::sim
{
class ClearanceGrid
{
   public:
    ClearanceGrid(const std::vector<Eigen::Vector3f>& positions, float cell_m);
    /** Minimum distance between any position and any triangle of `mesh`, or max_m if none is closer. */
    float minDistance(const Mesh& mesh, float max_m) const;
    /** Same for a single point set query: minimum distance from any position to point p. */
    float minDistanceToPoint(const Eigen::Vector3f& p, float max_m) const;
    bool empty() const { return positions_.empty(); }

   private:
    int64_t key(int x, int y, int z) const
    {
        return (int64_t(x) * 73856093) ^ (int64_t(y) * 19349663) ^ (int64_t(z) * 83492791);
    }
    std::vector<Eigen::Vector3f> positions_;
    float cell_;
    std::unordered_map<int64_t, std::vector<uint32_t>> cells_;
};

}  // namespace quasiloc::sim
