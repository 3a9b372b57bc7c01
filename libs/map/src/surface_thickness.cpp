#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <quasiloc/map/surface_thickness.h>
#include <quasiloc/map/voxel_hash.h>
#include <random>
#include <sstream>
#include <vector>

namespace quasiloc::map
{
namespace
{
/** The sample points: a fixed-seed pseudo-random choice, so a map gives the same figure on every run. */
std::vector<size_t> samplePoints(size_t n, int samples)
{
    std::vector<size_t> out;
    if (n == 0) return out;
    std::mt19937_64 rng(1);
    std::uniform_int_distribution<size_t> pick(0, n - 1);
    out.reserve(size_t(samples));
    for (int i = 0; i < samples; ++i) out.push_back(pick(rng));
    return out;
}

/** Square root of the patch's smallest eigenvalue, or a negative value when the patch is no surface. */
double patchThickness(const Eigen::Vector3f& centre, const std::vector<const std::vector<Eigen::Vector3f>*>& cells,
                      const SurfaceThicknessOptions& o)
{
    const float r2 = float(o.radius_m * o.radius_m);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d sq = Eigen::Matrix3d::Zero();
    int count = 0;
    for (const auto* cell : cells)
        for (const Eigen::Vector3f& p : *cell)
        {
            if ((p - centre).squaredNorm() > r2) continue;
            const Eigen::Vector3d q = (p - centre).cast<double>();
            sum += q;
            sq += q * q.transpose();
            ++count;
        }
    if (count < o.min_points) return -1;
    const Eigen::Vector3d mean = sum / count;
    const Eigen::Matrix3d cov = sq / count - mean * mean.transpose();
    const Eigen::Vector3d ev =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov, Eigen::EigenvaluesOnly).eigenvalues();
    if (ev[1] < o.min_spread_ratio * ev[2]) return -1;
    return std::sqrt(std::max(0.0, ev[0]));
}

double quantile(std::vector<double> v, double q)
{
    const size_t k = std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5));
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
    return v[k];
}
}  // namespace

SurfaceThickness measureSurfaceThickness(const LidarMap& map, const SurfaceThicknessOptions& o)
{
    SurfaceThickness out;
    const std::vector<size_t> seeds = samplePoints(map.size(), o.samples);
    const float inv = float(1.0 / o.radius_m);
    // The cells around every sample, then one pass over the map filling only those: the memory is that of the
    // patches, not of the map.
    VoxelHashMap<int> cell_index(size_t(o.samples) * 32);
    std::vector<std::vector<Eigen::Vector3f>> cells;
    for (size_t s : seeds)
    {
        const Eigen::Vector3i c = voxelOf(map.point(s), inv);
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx)
                {
                    VoxelKey key = 0;
                    if (!packVoxel(c + Eigen::Vector3i(dx, dy, dz), key)) continue;
                    int& slot = cell_index[key];
                    if (slot == 0)
                    {
                        cells.emplace_back();
                        slot = int(cells.size());  // 1-based: 0 is "not yet a cell"
                    }
                }
    }
    for (size_t i = 0; i < map.size(); ++i)
    {
        VoxelKey key = 0;
        if (!packVoxel(voxelOf(map.point(i), inv), key)) continue;
        if (const int* slot = cell_index.find(key)) cells[size_t(*slot - 1)].push_back(map.point(i));
    }
    std::vector<double> thickness;
    std::vector<const std::vector<Eigen::Vector3f>*> around;
    for (size_t s : seeds)
    {
        const Eigen::Vector3i c = voxelOf(map.point(s), inv);
        around.clear();
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx)
                {
                    VoxelKey key = 0;
                    if (!packVoxel(c + Eigen::Vector3i(dx, dy, dz), key)) continue;
                    if (const int* slot = cell_index.find(key)) around.push_back(&cells[size_t(*slot - 1)]);
                }
        ++out.sampled_patches;
        const double t = patchThickness(map.point(s), around, o);
        if (t >= 0) thickness.push_back(t);
    }
    out.surface_patches = thickness.size();
    if (thickness.empty()) return out;
    out.median_m = quantile(thickness, 0.5);
    out.p90_m = quantile(thickness, 0.9);
    return out;
}

std::string describe(const SurfaceThickness& t)
{
    std::ostringstream s;
    s.setf(std::ios::fixed);
    s.precision(1);
    s << "median " << t.median_m * 1e3 << " mm, p90 " << t.p90_m * 1e3 << " mm (" << t.surface_patches << " of "
      << t.sampled_patches << " patches are surfaces)";
    return s.str();
}

}  // namespace quasiloc::map
