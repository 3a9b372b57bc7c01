#pragma once
// map-import: a point cloud file (PLY, PCD, KITTI .bin, x y z i text) -> a quasiloc LidarMap file.
#include <mrpt/config/CLoadableOptions.h>

#include <quasiloc/core/program_options.h>
#include <string>

namespace quasiloc::map_import
{
/** Section [MapImport]. */
struct MapImportOptions : public mrpt::config::CLoadableOptions
{
    std::string input;             ///< point cloud to import
    std::string output;            ///< the LidarMap file to write (MRPT serialized CPointsMapXYZI, gz)
    std::string format = "auto";   ///< auto | ply | pcd | kitti | xyzi
    double voxel_size_m = 0.0;     ///< 0 = keep every point
    double intensity_scale = 0.0;  ///< 0 = automatic normalisation rule
    std::string export_cloud;      ///< optional: also write the imported map as .ply/.pcd/.bin/.txt
    std::string export_encoding = "binary";  ///< ascii | binary | binary_big_endian | binary_compressed

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
    /** InputError naming the key for a bad value. */
    void check(const std::string& config_name) const;
};

extern const char* const kUsage;

/** The program body for core::runProgram. */
int run(const core::CommandLine& cmd);

}  // namespace quasiloc::map_import
