#include "geometric_classes.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <unordered_map>

namespace quasiloc::bench
{
namespace
{
using sim::SurfaceClass;

int64_t voxelKey(int64_t x, int64_t y, int64_t z)
{
    return (x + (1 << 20)) | ((y + (1 << 20)) << 21) | ((z + (1 << 20)) << 42);
}

/** Points sorted into cubic cells of side `cell` for radius searches of at most `cell`. */
class PointGrid
{
   public:
    PointGrid(const map::LidarMap& m, double cell) : map_(m), inv_(1.0 / cell)
    {
        std::vector<std::pair<int64_t, uint32_t>> keyed(m.size());
        for (size_t i = 0; i < m.size(); ++i) keyed[i] = {keyOf(m.point(i)), uint32_t(i)};
        std::sort(keyed.begin(), keyed.end());
        order_.resize(keyed.size());
        for (size_t i = 0; i < keyed.size(); ++i)
        {
            order_[i] = keyed[i].second;
            if (i == 0 || keyed[i].first != keyed[i - 1].first) ranges_[keyed[i].first] = {uint32_t(i), uint32_t(i)};
            ranges_[keyed[i].first].second = uint32_t(i + 1);
        }
    }
    int64_t keyOf(const Eigen::Vector3f& p) const
    {
        return voxelKey(int64_t(std::floor(p.x() * inv_)), int64_t(std::floor(p.y() * inv_)),
                        int64_t(std::floor(p.z() * inv_)));
    }
    /** Indices of the points within r of p (r <= the cell side). */
    void neighbours(const Eigen::Vector3f& p, float r, std::vector<uint32_t>& out) const
    {
        out.clear();
        const int64_t cx = int64_t(std::floor(p.x() * inv_)), cy = int64_t(std::floor(p.y() * inv_)),
                      cz = int64_t(std::floor(p.z() * inv_));
        for (int64_t dz = -1; dz <= 1; ++dz)
            for (int64_t dy = -1; dy <= 1; ++dy)
                for (int64_t dx = -1; dx <= 1; ++dx)
                {
                    const auto it = ranges_.find(voxelKey(cx + dx, cy + dy, cz + dz));
                    if (it == ranges_.end()) continue;
                    for (uint32_t k = it->second.first; k < it->second.second; ++k)
                        if ((map_.point(order_[k]) - p).squaredNorm() <= r * r) out.push_back(order_[k]);
                }
    }

   private:
    const map::LidarMap& map_;
    double inv_;
    std::vector<uint32_t> order_;
    std::unordered_map<int64_t, std::pair<uint32_t, uint32_t>> ranges_;
};

/** Eigen-features of a point's neighbourhood. */
struct LocalShape
{
    float up = 0;         ///< |n_z| of the normal (smallest eigenvector)
    float planarity = 0;  ///< (l2 - l3) / l1
    float scatter = 0;    ///< l3 / l1
    float rough = 0;      ///< sqrt(l3): spread along the normal, metres
    bool valid = false;
};

std::vector<LocalShape> localShapes(const map::LidarMap& m, double radius)
{
    const PointGrid grid(m, radius);
    std::vector<LocalShape> out(m.size());
    std::vector<uint32_t> nb;
    for (size_t i = 0; i < m.size(); ++i)
    {
        grid.neighbours(m.point(i), float(radius), nb);
        if (nb.size() < 6) continue;
        const size_t step = std::max<size_t>(1, nb.size() / 64);  // at most ~64 neighbours: enough for 3 eigenvalues
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
        size_t n = 0;
        for (size_t k = 0; k < nb.size(); k += step, ++n) mean += m.point(nb[k]).cast<double>();
        mean /= double(n);
        for (size_t k = 0; k < nb.size(); k += step)
        {
            const Eigen::Vector3d d = m.point(nb[k]).cast<double>() - mean;
            cov += d * d.transpose();
        }
        cov /= double(n);
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
        const Eigen::Vector3d l = es.eigenvalues().cwiseMax(0.0);  // ascending
        if (l[2] <= 0) continue;
        LocalShape& s = out[i];
        s.up = float(std::abs(es.eigenvectors().col(0).z()));
        s.planarity = float((l[1] - l[0]) / l[2]);
        s.scatter = float(l[0] / l[2]);
        s.rough = float(std::sqrt(l[0]));
        s.valid = true;
    }
    return out;
}

/** Ground height on a 2D grid (see geometric_classes.h, step 1). */
class GroundGrid
{
   public:
    GroundGrid(const map::LidarMap& m, double cell, double max_step) : cell_(cell)
    {
        const map::MapBounds b = m.bounds();
        x0_ = b.min.x(), y0_ = b.min.y();
        nx_ = int(std::floor((b.max.x() - x0_) / cell)) + 1;
        ny_ = int(std::floor((b.max.y() - y0_) / cell)) + 1;
        std::vector<std::vector<float>> zs(size_t(nx_) * ny_);
        for (size_t i = 0; i < m.size(); ++i) zs[index(m.xs()[i], m.ys()[i])].push_back(m.zs()[i]);
        h_.assign(zs.size(), NAN);
        for (size_t c = 0; c < zs.size(); ++c)
        {
            auto& z = zs[c];
            if (z.size() < 5) continue;
            const size_t k = z.size() / 20;
            std::nth_element(z.begin(), z.begin() + long(k), z.end());
            h_[c] = z[k];
        }
        // Cells above their neighbourhood (only a vehicle's or a wall's points in them) and empty cells take the
        // median of the 5 x 5 cells around them; a few passes fill holes from their rims.
        for (int pass = 0; pass < 6; ++pass)
        {
            std::vector<float> next = h_;
            for (int cy = 0; cy < ny_; ++cy)
                for (int cx = 0; cx < nx_; ++cx)
                {
                    std::vector<float> around;
                    for (int dy = -2; dy <= 2; ++dy)
                        for (int dx = -2; dx <= 2; ++dx)
                        {
                            const int x = cx + dx, y = cy + dy;
                            if (x < 0 || y < 0 || x >= nx_ || y >= ny_) continue;
                            const float v = h_[size_t(y) * nx_ + x];
                            if (std::isfinite(v)) around.push_back(v);
                        }
                    if (around.size() < 3) continue;
                    std::nth_element(around.begin(), around.begin() + long(around.size() / 2), around.end());
                    const float med = around[around.size() / 2];
                    float& h = next[size_t(cy) * nx_ + cx];
                    if (!std::isfinite(h) || h > med + float(max_step)) h = med;
                }
            h_.swap(next);
        }
    }
    size_t index(float x, float y) const
    {
        const int cx = std::clamp(int(std::floor((x - x0_) / cell_)), 0, nx_ - 1);
        const int cy = std::clamp(int(std::floor((y - y0_) / cell_)), 0, ny_ - 1);
        return size_t(cy) * nx_ + cx;
    }
    size_t cells() const { return h_.size(); }
    int nx() const { return nx_; }
    int ny() const { return ny_; }
    /** Bilinear between cell centres; NaN where no cell around has a height. */
    float height(float x, float y) const
    {
        const double fx = (x - x0_) / cell_ - 0.5, fy = (y - y0_) / cell_ - 0.5;
        const int ix = int(std::floor(fx)), iy = int(std::floor(fy));
        const double tx = fx - ix, ty = fy - iy;
        double sum = 0, wsum = 0;
        for (int dy = 0; dy <= 1; ++dy)
            for (int dx = 0; dx <= 1; ++dx)
            {
                const int cx = std::clamp(ix + dx, 0, nx_ - 1), cy = std::clamp(iy + dy, 0, ny_ - 1);
                const float h = h_[size_t(cy) * nx_ + cx];
                if (!std::isfinite(h)) continue;
                const double w = (dx ? tx : 1 - tx) * (dy ? ty : 1 - ty);
                sum += w * h, wsum += w;
            }
        return wsum > 1e-9 ? float(sum / wsum) : NAN;
    }

   private:
    double cell_, x0_ = 0, y0_ = 0;
    int nx_ = 1, ny_ = 1;
    std::vector<float> h_;
};

/** A 2D occupancy grid over the map's footprint (cells of side `cell`). */
struct Grid2D
{
    double x0 = 0, y0 = 0, cell = 1;
    int nx = 1, ny = 1;
    Grid2D(const map::MapBounds& b, double c) : x0(b.min.x()), y0(b.min.y()), cell(c)
    {
        nx = int(std::floor((b.max.x() - x0) / c)) + 1;
        ny = int(std::floor((b.max.y() - y0) / c)) + 1;
    }
    size_t index(float x, float y) const
    {
        const int cx = std::clamp(int(std::floor((x - x0) / cell)), 0, nx - 1);
        const int cy = std::clamp(int(std::floor((y - y0) / cell)), 0, ny - 1);
        return size_t(cy) * nx + cx;
    }
};
}  // namespace

void GeometricClassOptions::declare(core::OptionTable& t)
{
    const core::Range pos = core::Range::above(0), unit = core::Range::between(0, 1);
    t.add("ground_cell_m", ground_cell_m, "m", pos, "ground height grid cell");
    t.add("ground_band_m", ground_band_m, "m", pos, "points this close above the ground height are ground");
    t.add("ground_max_step_m", ground_max_step_m, "m", pos,
          "a ground cell this far above its neighbourhood is lowered");
    t.add("feature_radius_m", feature_radius_m, "m", pos, "neighbourhood of the local eigen-features");
    t.add("road_min_up", road_min_up, "", unit, "road: |n_z| of the local normal at least this");
    t.add("road_max_rough_m", road_max_rough_m, "m", pos, "road: spread along the normal at most this");
    t.add("marking_delta", marking_delta, "", unit, "marking: brighter than its ground cell's road median by this");
    t.add("marking_min", marking_min, "", unit, "marking: reflectivity at least this");
    t.add("region_cell_m", region_cell_m, "m", pos, "cells of the road region and of the column heights");
    t.add("vehicle_reach_m", vehicle_reach_m, "m", pos, "the road region reaches this far beyond road points");
    t.add("vehicle_max_height_m", vehicle_max_height_m, "m", pos, "vehicle: at most this high above the ground");
    t.add("vegetation_min_scatter", vegetation_min_scatter, "", unit, "vegetation: l3 / l1 at least this");
    t.add("facade_min_planarity", facade_min_planarity, "", unit, "facade: (l2 - l3) / l1 at least this");
    t.add("facade_max_up", facade_max_up, "", unit, "facade: |n_z| at most this");
    t.add("facade_min_height_m", facade_min_height_m, "m", pos, "facade: its column at least this tall");
}

std::vector<uint8_t> classifyGeometrically(const map::LidarMap& m, const GeometricClassOptions& o,
                                           GeometricClassStats* stats)
{
    const auto t0 = std::chrono::steady_clock::now();
    const size_t n = m.size();
    std::vector<uint8_t> cls(n, uint8_t(SurfaceClass::other));
    const std::vector<LocalShape> shape = localShapes(m, o.feature_radius_m);
    const GroundGrid ground(m, o.ground_cell_m, o.ground_max_step_m);

    // Ground, road and the road's reflectivity per ground cell.
    std::vector<float> above(n);
    std::vector<std::vector<float>> road_refl(ground.cells());
    std::vector<char> is_ground(n, 0);
    for (size_t i = 0; i < n; ++i)
    {
        const float h = ground.height(m.xs()[i], m.ys()[i]);
        above[i] = std::isfinite(h) ? m.zs()[i] - h : 1e3f;
        if (above[i] > o.ground_band_m || above[i] < -3 * o.ground_band_m) continue;
        is_ground[i] = 1;
        const LocalShape& s = shape[i];
        if (s.valid && s.up >= o.road_min_up && s.rough <= o.road_max_rough_m)
        {
            cls[i] = uint8_t(SurfaceClass::road);
            road_refl[ground.index(m.xs()[i], m.ys()[i])].push_back(m.reflectivity(i));
        }
    }
    std::vector<float> road_median(ground.cells(), NAN);
    for (size_t c = 0; c < road_refl.size(); ++c)
    {
        auto& r = road_refl[c];
        if (r.size() < 10) continue;
        std::nth_element(r.begin(), r.begin() + long(r.size() / 2), r.end());
        road_median[c] = r[r.size() / 2];
    }
    for (size_t i = 0; i < n; ++i)
    {
        if (cls[i] != uint8_t(SurfaceClass::road)) continue;
        const float med = road_median[ground.index(m.xs()[i], m.ys()[i])];
        const float r = m.reflectivity(i);
        if (std::isfinite(med) && r >= med + o.marking_delta && r >= o.marking_min)
            cls[i] = uint8_t(SurfaceClass::marking);
    }

    // The road region: cells holding road points, closed and grown by vehicle_reach_m (what stands on the road
    // hides the road under it); the height of every column above the ground.
    const Grid2D grid(m.bounds(), o.region_cell_m);
    cv::Mat road_cells = cv::Mat::zeros(grid.ny, grid.nx, CV_8U);
    cv::Mat column_top = cv::Mat::zeros(grid.ny, grid.nx, CV_32F);
    for (size_t i = 0; i < n; ++i)
    {
        const size_t c = grid.index(m.xs()[i], m.ys()[i]);
        if (cls[i] == uint8_t(SurfaceClass::road) || cls[i] == uint8_t(SurfaceClass::marking)) road_cells.data[c] = 255;
        float& top = column_top.ptr<float>()[c];
        if (above[i] < 100) top = std::max(top, above[i]);
    }
    const int reach = std::max(1, int(std::lround(o.vehicle_reach_m / o.region_cell_m)));
    const cv::Mat disc = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * reach + 1, 2 * reach + 1));
    cv::Mat region;
    cv::morphologyEx(road_cells, region, cv::MORPH_CLOSE, disc);
    cv::dilate(region, region, disc);

    GeometricClassStats st;
    st.road_region_m2 = double(cv::countNonZero(region)) * o.region_cell_m * o.region_cell_m;
    for (size_t i = 0; i < n; ++i)
    {
        if (is_ground[i]) continue;
        const size_t c = grid.index(m.xs()[i], m.ys()[i]);
        const LocalShape& s = shape[i];
        if (region.data[c] && above[i] <= o.vehicle_max_height_m)
            cls[i] = uint8_t(SurfaceClass::vehicle);
        else if (s.valid && s.scatter >= o.vegetation_min_scatter)
            cls[i] = uint8_t(SurfaceClass::vegetation);
        else if (s.valid && s.planarity >= o.facade_min_planarity && s.up <= o.facade_max_up &&
                 column_top.ptr<float>()[c] >= o.facade_min_height_m)
            cls[i] = uint8_t(SurfaceClass::facade);
    }
    for (uint8_t c : cls) ++st.points[c];
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (stats) *stats = st;
    return cls;
}

}  // namespace quasiloc::bench
