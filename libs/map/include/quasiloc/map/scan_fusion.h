#pragma once
// Voxel fusion of scans into a map, and the self-calibration of their reflectivity.
//
// VoxelFusion: the space is cut into cubes of voxel_m aligned with the world origin; each occupied cube becomes one
// map point at the mean position of its points, with the mean reflectivity of its points. Memory grows with the
// occupied volume, not with the number of scans (about 64 bytes per occupied voxel at half load).
//
// ReflectivityModel: raw intensities are not reflectivities. Each laser has its own gain and the return weakens
// (or the sensor's own compensation over-corrects) with range. The model is multiplicative,
//     raw = reflectivity * g(ring) * h(range bin),
// fitted without a calibration target from the map itself: a voxel seen from several rings and ranges has one
// reflectivity, so log(raw / the voxel's mean raw) averaged per (ring, range bin) measures g * h relative to the
// other cells (an unsupervised calibration in the spirit of Levinson & Thrun, RSS 2010, reduced to one gain per
// ring and per range bin). g and h are fitted by alternating weighted means of those log offsets, each normalised
// to a geometric mean of 1, so the overall scale stays the raw one (then divided by the import rule's divisor,
// map_import.h). Only voxels with >= 3 points and raw values >= 0.01 (log of zero) enter the fit.
#include <Eigen/Core>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/map/voxel_hash.h>
#include <quasiloc/map/world_scan.h>
#include <string>
#include <vector>

namespace quasiloc::map
{
class ReflectivityModel;

struct FusedVoxel
{
    float sum[3] = {0, 0, 0};  ///< of the points' offsets from the voxel's corner
    uint32_t count = 0;
    float raw_sum = 0, raw_sq = 0;    ///< raw intensities
    float refl_sum = 0, refl_sq = 0;  ///< normalised reflectivities (addReflectivity)
};

/** Mean coefficient of variation (std / mean) of the observations within a voxel, over voxels with >= 3 points and
 *  a mean above 0.01: how far a voxel's observations disagree (lower: more consistent reflectivity). */
struct ReflectivityConsistency
{
    double raw_cv = 0, normalised_cv = 0;
    size_t voxels = 0;
};

class VoxelFusion
{
   public:
    explicit VoxelFusion(double voxel_m);
    double voxelSize() const { return voxel_m_; }
    /** Positions and raw intensities of a scan's points. InputError naming `scan_name` for a point beyond the key
     *  range (+-2^20 voxels). */
    void addGeometry(const WorldScan& scan, const std::string& scan_name);
    /** The normalised reflectivities of the same scan's points (after addGeometry of every scan). */
    void addReflectivity(const WorldScan& scan, const ReflectivityModel& model);

    size_t size() const { return voxels_.size(); }
    size_t memoryBytes() const { return voxels_.memoryBytes(); }
    const FusedVoxel* find(const Eigen::Vector3f& p) const;
    /** The voxel's mean raw intensity (0 if absent). */
    float rawMean(const Eigen::Vector3f& p) const;
    ReflectivityConsistency consistency() const;

    /** f(mean position, voxel) for every voxel. */
    template <class F>
    void forEachPoint(F&& f) const
    {
        voxels_.forEach([&](VoxelKey key, const FusedVoxel& v) {
            const Eigen::Vector3f corner = unpackVoxel(key).cast<float>() * float(voxel_m_);
            const Eigen::Vector3f mean = corner + Eigen::Vector3f(v.sum[0], v.sum[1], v.sum[2]) / float(v.count);
            f(mean, v);
        });
    }

   private:
    double voxel_m_;
    float inv_;
    VoxelHashMap<FusedVoxel> voxels_;
};

class ReflectivityModel
{
   public:
    /** per_ring / per_range: which factors are fitted (neither: every gain is 1). */
    ReflectivityModel(bool per_ring, bool per_range, double range_bin_m, double max_range_m);
    /** Adds a scan's log offsets from its voxels' raw means (after addGeometry of every scan). */
    void observe(const WorldScan& scan, const VoxelFusion& fusion);
    /** Fits g and h to the observed offsets. */
    void fit();
    /** raw / (g(ring) * h(range)). */
    float correct(float raw, int ring, float range_m) const { return raw * ringFactor(ring) * rangeFactor(range_m); }
    float ringFactor(int ring) const { return ring >= 0 && ring < int(inv_g_.size()) ? inv_g_[size_t(ring)] : 1.f; }
    float rangeFactor(float range_m) const
    {
        const int b = int(range_m / bin_m_);
        return b >= 0 && b < int(inv_h_.size()) ? inv_h_[size_t(b)] : 1.f;
    }
    bool perRing() const { return per_ring_; }
    bool perRange() const { return per_range_; }
    /** Human-readable: the fitted gains (range bins and the rings' spread). */
    std::string summary() const;

   private:
    static constexpr int kMaxRings = 256;
    bool per_ring_, per_range_;
    double bin_m_;
    int bins_;
    std::vector<double> sum_, count_;  ///< per (ring, bin) cell: sum of log offsets and count
    std::vector<float> inv_g_, inv_h_;
    std::vector<double> g_log_, h_log_;
};

}  // namespace quasiloc::map
