#include <cmath>
#include <iomanip>
#include <quasiloc/core/error.h>
#include <quasiloc/map/scan_fusion.h>
#include <sstream>

namespace quasiloc::map
{
VoxelFusion::VoxelFusion(double voxel_m) : voxel_m_(voxel_m), inv_(float(1.0 / voxel_m)), voxels_(1 << 16) {}

void VoxelFusion::addGeometry(const WorldScan& scan, const std::string& scan_name)
{
    for (size_t k = 0; k < scan.size(); ++k)
    {
        const Eigen::Vector3f& p = scan.points[k];
        const Eigen::Vector3i v = voxelOf(p, inv_);
        VoxelKey key = 0;
        if (!packVoxel(v, key))
            throw core::InputError(scan_name, "a point lies beyond the map's reach (+-2^20 voxels of " +
                                                  std::to_string(voxel_m_) + " m from the world origin)");
        FusedVoxel& f = voxels_[key];
        const Eigen::Vector3f offset = p - v.cast<float>() * float(voxel_m_);
        for (int a = 0; a < 3; ++a) f.sum[a] += offset[a];
        ++f.count;
        f.raw_sum += scan.intensity[k];
        f.raw_sq += scan.intensity[k] * scan.intensity[k];
    }
}

void VoxelFusion::addReflectivity(const WorldScan& scan, const ReflectivityModel& model)
{
    for (size_t k = 0; k < scan.size(); ++k)
    {
        VoxelKey key = 0;
        if (!packVoxel(voxelOf(scan.points[k], inv_), key)) continue;
        FusedVoxel* f = voxels_.find(key);
        if (f == nullptr) continue;
        const float r = model.correct(scan.intensity[k], scan.ring.empty() ? -1 : scan.ring[k], scan.range_m[k]);
        f->refl_sum += r;
        f->refl_sq += r * r;
    }
}

const FusedVoxel* VoxelFusion::find(const Eigen::Vector3f& p) const
{
    VoxelKey key = 0;
    return packVoxel(voxelOf(p, inv_), key) ? voxels_.find(key) : nullptr;
}

float VoxelFusion::rawMean(const Eigen::Vector3f& p) const
{
    const FusedVoxel* f = find(p);
    return f != nullptr && f->count > 0 ? f->raw_sum / float(f->count) : 0.f;
}

ReflectivityConsistency VoxelFusion::consistency() const
{
    ReflectivityConsistency c;
    auto cv = [](double sum, double sq, double n) {
        const double mean = sum / n;
        return std::sqrt(std::max(0.0, sq / n - mean * mean)) / mean;
    };
    voxels_.forEach([&](VoxelKey, const FusedVoxel& v) {
        if (v.count < 3 || v.raw_sum / v.count < 0.01 || v.refl_sum / v.count < 0.01) return;
        c.raw_cv += cv(v.raw_sum, v.raw_sq, v.count);
        c.normalised_cv += cv(v.refl_sum, v.refl_sq, v.count);
        ++c.voxels;
    });
    if (c.voxels > 0) c.raw_cv /= double(c.voxels), c.normalised_cv /= double(c.voxels);
    return c;
}

ReflectivityModel::ReflectivityModel(bool per_ring, bool per_range, double range_bin_m, double max_range_m)
    : per_ring_(per_ring),
      per_range_(per_range),
      bin_m_(range_bin_m),
      bins_(std::max(1, int(std::ceil(max_range_m / range_bin_m)))),
      sum_(size_t(kMaxRings) * size_t(bins_), 0.0),
      count_(sum_.size(), 0.0),
      inv_g_(per_ring ? kMaxRings : 0, 1.f),
      inv_h_(per_range ? bins_ : 0, 1.f),
      g_log_(kMaxRings, 0.0),
      h_log_(size_t(bins_), 0.0)
{}

void ReflectivityModel::observe(const WorldScan& scan, const VoxelFusion& fusion)
{
    if (!per_ring_ && !per_range_) return;
    for (size_t k = 0; k < scan.size(); ++k)
    {
        const float raw = scan.intensity[k];
        if (raw < 0.01f) continue;
        const FusedVoxel* f = fusion.find(scan.points[k]);
        if (f == nullptr || f->count < 3) continue;
        const float mean = f->raw_sum / float(f->count);
        if (mean < 0.01f) continue;
        const int ring = per_ring_ && !scan.ring.empty() ? std::min<int>(scan.ring[k], kMaxRings - 1) : 0;
        const int bin = per_range_ ? std::min(bins_ - 1, int(scan.range_m[k] / bin_m_)) : 0;
        const size_t cell = size_t(ring) * size_t(bins_) + size_t(bin);
        sum_[cell] += std::log(raw / mean);
        count_[cell] += 1;
    }
}

void ReflectivityModel::fit()
{
    if (!per_ring_ && !per_range_) return;
    // Alternating weighted means: g_r = mean over bins of (offset - h_b), h_b = mean over rings of (offset - g_r).
    for (int iteration = 0; iteration < 30; ++iteration)
    {
        if (per_ring_)
            for (int r = 0; r < kMaxRings; ++r)
            {
                double s = 0, n = 0;
                for (int b = 0; b < bins_; ++b)
                {
                    const size_t c = size_t(r) * size_t(bins_) + size_t(b);
                    s += sum_[c] - count_[c] * h_log_[size_t(b)];
                    n += count_[c];
                }
                g_log_[size_t(r)] = n >= 100 ? s / n : 0.0;
            }
        if (per_range_)
            for (int b = 0; b < bins_; ++b)
            {
                double s = 0, n = 0;
                for (int r = 0; r < kMaxRings; ++r)
                {
                    const size_t c = size_t(r) * size_t(bins_) + size_t(b);
                    s += sum_[c] - count_[c] * g_log_[size_t(r)];
                    n += count_[c];
                }
                h_log_[size_t(b)] = n >= 100 ? s / n : 0.0;
            }
    }
    // Geometric mean 1 over the observations, so the overall scale stays the raw one.
    auto centre = [&](std::vector<double>& f, bool rings) {
        double s = 0, n = 0;
        for (int r = 0; r < kMaxRings; ++r)
            for (int b = 0; b < bins_; ++b)
            {
                const double c = count_[size_t(r) * size_t(bins_) + size_t(b)];
                s += c * f[size_t(rings ? r : b)];
                n += c;
            }
        if (n > 0)
            for (double& v : f) v -= s / n;
    };
    if (per_ring_) centre(g_log_, true);
    if (per_range_) centre(h_log_, false);
    for (size_t r = 0; r < inv_g_.size(); ++r) inv_g_[r] = float(std::exp(-g_log_[r]));
    for (size_t b = 0; b < inv_h_.size(); ++b) inv_h_[b] = float(std::exp(-h_log_[b]));
}

std::string ReflectivityModel::summary() const
{
    std::ostringstream s;
    s << std::fixed << std::setprecision(2);
    if (!per_ring_ && !per_range_) return "reflectivity = raw intensity (no ring or range gain)";
    if (per_range_)
    {
        s << "range gain h (x" << bin_m_ << " m bins):";
        for (int b = 0; b < bins_; ++b)
        {
            double n = 0;
            for (int r = 0; r < kMaxRings; ++r) n += count_[size_t(r) * size_t(bins_) + size_t(b)];
            if (n > 0) s << " " << std::exp(h_log_[size_t(b)]);
        }
        s << "\n";
    }
    if (per_ring_)
    {
        double lo = 1e9, hi = 0;
        int rings = 0;
        for (int r = 0; r < kMaxRings; ++r)
        {
            double n = 0;
            for (int b = 0; b < bins_; ++b) n += count_[size_t(r) * size_t(bins_) + size_t(b)];
            if (n < 100) continue;
            ++rings;
            lo = std::min(lo, std::exp(g_log_[size_t(r)]));
            hi = std::max(hi, std::exp(g_log_[size_t(r)]));
        }
        if (rings == 0)
            s << "ring gain g: no ring with enough observations (the scans carry no ring numbers?)\n";
        else
            s << "ring gain g: " << rings << " rings, from " << lo << " to " << hi << "\n";
    }
    std::string text = s.str();
    if (!text.empty() && text.back() == '\n') text.pop_back();
    return text;
}

}  // namespace quasiloc::map
