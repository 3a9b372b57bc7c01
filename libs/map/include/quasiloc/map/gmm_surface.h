#pragma once
// A LidarMap from a Gaussian-mixture map (gmm.h) by sampling each component's surface.
//
// Each component is read as a flat patch: the covariance's eigenvectors give two in-plane axes (the two
// largest standard deviations sigma_max, sigma_mid) and the normal (the smallest, sigma_min). The surface is
// the ellipse on the component's mean spanned by the two in-plane axes with semi-axes
// truncation_sigma * sigma_max and truncation_sigma * sigma_mid. truncation_sigma = 2 recovers the extent of
// a uniformly filled disc exactly (sigma = R/2) and of a uniform rectangle nearly (2 sigma = 1.15 half-width).
//
// Sampling: a stratified-jittered grid in the ellipse's own axes, spacing 1/sqrt(density_per_m2), one
// uniformly jittered point per cell, kept when inside the ellipse. The expected count is exactly
// density_per_m2 * area (also for ellipses smaller than one cell), without the moire of a regular grid.
// Each component draws from its own generator seeded by (seed, component index): the result is deterministic
// for a seed and does not depend on the other components.
//
// Components that are not surface-like, sigma_min / sigma_mid > max_flatness (a blob rather than a patch;
// also a component with sigma_mid = 0), are skipped and counted. GMMLoc's is_degenerated flag (the smallest
// eigenvalue was clamped, i.e. flat) is only counted: the eigenvalues already say how flat a component is.
// On the EuRoC v1 room, 3154 of 3299 components are flagged degenerated; sigma_min / sigma_mid has median
// 0.033, 94 components exceed 0.5 (46 of them flagged degenerated), and skipping them or not changes the
// line-map check's median by about 0.1 mm (README, "A map of the real EuRoC rooms").
//
// Reflectivity is unknown in a GMM: every point gets the constant `reflectivity`.
#include <mrpt/system/CTimeLogger.h>

#include <Eigen/Core>
#include <cstdint>
#include <quasiloc/map/gmm.h>
#include <quasiloc/map/lidar_map.h>
#include <string>
#include <vector>

namespace quasiloc::map
{
struct GmmSurfaceOptions
{
    double density_per_m2 = 2500.0;  ///< points per square metre of surface (2500 = 2 cm spacing)
    double truncation_sigma = 2.0;   ///< ellipse semi-axes in standard deviations
    double max_flatness = 0.5;       ///< skip when sigma_min / sigma_mid exceeds this; 1 = sample all with an area
    double reflectivity = 0.5;       ///< constant reflectivity of every point, in [0, 1]
    uint64_t seed = 1;               ///< jitter generator seed

    /** InputError naming key_prefix + the option (e.g. "[MapImport] gmm_" + "density_per_m2") for a value
     *  out of range. */
    void check(const std::string& key_prefix) const;
};

/** The sampled surface of one component. */
struct GmmComponentSurface
{
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
    Eigen::Vector3d axis_u = Eigen::Vector3d::UnitX();  ///< unit, along sigma_max
    Eigen::Vector3d axis_v = Eigen::Vector3d::UnitY();  ///< unit, along sigma_mid
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< unit, along sigma_min
    Eigen::Vector3d sigmas = Eigen::Vector3d::Zero();   ///< sigma_min, sigma_mid, sigma_max (metres)
    double semi_u_m = 0, semi_v_m = 0;                  ///< truncation_sigma * sigma_max, * sigma_mid
    double flatness = 1;  ///< sigma_min / sigma_mid (infinite when sigma_mid = 0: no surface)
    double areaM2() const;
};

/** Eigen-decomposes the component's covariance (negative eigenvalues clamped to 0). */
GmmComponentSurface componentSurface(const GmmComponent& c, double truncation_sigma);

struct GmmSurfaceStats
{
    size_t components = 0;
    size_t sampled = 0;           ///< components that were sampled (some may have drawn no point)
    size_t skipped_not_flat = 0;  ///< sigma_min / sigma_mid > max_flatness
    size_t degenerated = 0;       ///< GMMLoc's is_degenerated flag set (counted only)
    size_t points = 0;
    double area_m2 = 0;  ///< summed area of the sampled ellipses (overlaps counted twice)
};

/** Samples every surface-like component (see above). InputError naming `input` and the component for a
 *  component whose ellipse would need more than 1e8 grid cells, and for bad options. */
LidarMap sampleGmmSurfaces(const std::vector<GmmComponent>& components, const GmmSurfaceOptions& options,
                           GmmSurfaceStats* stats = nullptr, const std::string& input = "GMM");

struct GmmImportResult
{
    LidarMap map;
    GmmSurfaceStats stats;
    size_t points_sampled = 0;  ///< before the optional voxel filter
};

/** readGmmFile -> sampleGmmSurfaces -> (voxelDownsample when voxel_size_m > 0); stages "import.read",
 *  "import.sample", "import.voxel" are timed in `timer` if given. */
GmmImportResult importGmm(const std::string& path, const GmmSurfaceOptions& options, double voxel_size_m,
                          mrpt::system::CTimeLogger* timer = nullptr);

}  // namespace quasiloc::map
