#pragma once
// map-import: a point cloud file (PLY, PCD, KITTI .bin, x y z i text) or a GMMLoc Gaussian-mixture map (.gmm,
// sampled on its components' surfaces) -> a quasiloc LidarMap file.
#include <mrpt/config/CLoadableOptions.h>

#include <quasiloc/core/program_options.h>
#include <quasiloc/map/gmm_surface.h>
#include <string>

namespace quasiloc::map_import
{
/** Section [MapImport]. */
struct MapImportOptions : public mrpt::config::CLoadableOptions
{
    std::string input;             ///< point cloud (or .gmm) to import
    std::string output;            ///< the LidarMap file to write (MRPT serialized CPointsMapXYZI, gz)
    std::string format = "auto";   ///< auto | ply | pcd | kitti | xyzi | gmm
    double voxel_size_m = 0.0;     ///< 0 = keep every point
    double intensity_scale = 0.0;  ///< 0 = automatic normalisation rule
    std::string export_cloud;      ///< optional: also write the imported map as .ply/.pcd/.bin/.txt
    std::string export_encoding = "binary";  ///< ascii | binary | binary_big_endian | binary_compressed
    // .gmm input only (see quasiloc/map/gmm_surface.h):
    double gmm_density_per_m2 = 2500.0;  ///< surface points per m2 (2 cm spacing)
    double gmm_truncation_sigma = 2.0;   ///< ellipse semi-axes in standard deviations
    double gmm_max_flatness = 0.5;       ///< skip components with sigma_min / sigma_mid above; 1 = none
    double gmm_reflectivity = 0.5;       ///< constant reflectivity (a GMM has none)
    uint64_t gmm_seed = 1;               ///< jitter seed (INI: an integer in [0, 1e9])

    /** format = gmm, or auto with a .gmm extension. */
    bool gmmInput() const;
    map::GmmSurfaceOptions gmmOptions() const;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
    /** InputError naming the key for a bad value. */
    void check(const std::string& config_name) const;
};

extern const char* const kUsage;

/** The program body for core::runProgram. */
int run(const core::CommandLine& cmd);

}  // namespace quasiloc::map_import
