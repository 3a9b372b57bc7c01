#include <cmath>
#include <quasiloc/sim/clearance_grid.h>

namespace quasiloc::sim
{
ClearanceGrid::ClearanceGrid(const std::vector<Eigen::Vector3f>& positions, float cell_m)
    : positions_(positions), cell_(cell_m)
{
    for (uint32_t i = 0; i < positions_.size(); ++i)
    {
        const Eigen::Vector3f& p = positions_[i];
        cells_[key(static_cast<int>(std::floor(p.x() / cell_)), static_cast<int>(std::floor(p.y() / cell_)),
                   static_cast<int>(std::floor(p.z() / cell_)))]
            .push_back(i);
    }
}

float ClearanceGrid::minDistance(const Mesh& mesh, float max_m) const
{
    float best2 = max_m * max_m;
    for (const Triangle& t : mesh.triangles)
    {
        const Eigen::Vector3f& a = mesh.vertices[t.v[0]].p;
        const Eigen::Vector3f& b = mesh.vertices[t.v[1]].p;
        const Eigen::Vector3f& c = mesh.vertices[t.v[2]].p;
        const float r = std::sqrt(best2);
        const Eigen::Vector3f lo = a.cwiseMin(b).cwiseMin(c).array() - r, hi = a.cwiseMax(b).cwiseMax(c).array() + r;
        const int x0 = static_cast<int>(std::floor(lo.x() / cell_)), x1 = static_cast<int>(std::floor(hi.x() / cell_));
        const int y0 = static_cast<int>(std::floor(lo.y() / cell_)), y1 = static_cast<int>(std::floor(hi.y() / cell_));
        const int z0 = static_cast<int>(std::floor(lo.z() / cell_)), z1 = static_cast<int>(std::floor(hi.z() / cell_));
        for (int x = x0; x <= x1; ++x)
            for (int y = y0; y <= y1; ++y)
                for (int z = z0; z <= z1; ++z)
                {
                    const auto it = cells_.find(key(x, y, z));
                    if (it == cells_.end()) continue;
                    for (uint32_t i : it->second)
                        best2 = std::min(best2, pointTriangleDistanceSquared(positions_[i], a, b, c));
                }
    }
    return std::sqrt(best2);
}

float ClearanceGrid::minDistanceToPoint(const Eigen::Vector3f& p, float max_m) const
{
    float best2 = max_m * max_m;
    const int r = static_cast<int>(std::ceil(max_m / cell_));
    const int cx = static_cast<int>(std::floor(p.x() / cell_)), cy = static_cast<int>(std::floor(p.y() / cell_)),
              cz = static_cast<int>(std::floor(p.z() / cell_));
    for (int x = cx - r; x <= cx + r; ++x)
        for (int y = cy - r; y <= cy + r; ++y)
            for (int z = cz - r; z <= cz + r; ++z)
            {
                const auto it = cells_.find(key(x, y, z));
                if (it == cells_.end()) continue;
                for (uint32_t i : it->second) best2 = std::min(best2, (positions_[i] - p).squaredNorm());
            }
    return std::sqrt(best2);
}

}  // namespace quasiloc::sim
