#pragma once
// map-import: a point cloud file (PLY, PCD, KITTI .bin, x y z i text) or a GMMLoc Gaussian-mixture map (.gmm,
// sampled on its components' surfaces) -> a quasiloc LidarMap file.
#include <quasiloc/core/declared_options.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/map/cloud_export.h>
#include <quasiloc/map/gmm_surface.h>
#include <string>

namespace quasiloc::map_import
{
/** What [MapImport] format names: a point cloud format (map::CloudFormat) or a GMMLoc Gaussian-mixture map. */
enum class InputFormat
{
    Auto,  ///< from the extension
    Ply,
    Pcd,
    Kitti,
    Xyzi,
    Gmm
};

/** Section [MapImport]; each key's unit, range and meaning: declare() (map_import_options.cpp). */
struct MapImportOptions : public core::DeclaredOptions
{
    std::string input;
    std::string output;
    InputFormat format = InputFormat::Auto;
    double voxel_size_m = 0.0;
    double intensity_scale = 0.0;
    std::string export_cloud;
    map::CloudEncoding export_encoding = map::CloudEncoding::Binary;
    double gmm_density_per_m2 = 2500.0;
    double gmm_truncation_sigma = 2.0;
    double gmm_max_flatness = 0.5;
    double gmm_reflectivity = 0.5;
    uint64_t gmm_seed = 1;

    /** format = gmm, or auto with a .gmm extension. */
    bool gmmInput() const;
    /** The point cloud format (not for gmmInput()). */
    map::CloudFormat cloudFormat() const;
    map::GmmSurfaceOptions gmmOptions() const;

    void declare(core::OptionTable& t) override;
    /** The declared ranges, then the rules between keys: InputError naming the key. */
    void check(const std::string& config_name) const;
};

/** --help: the usage, with the options listed from their declaration. */
std::string usage();
/** Each declared key of [MapImport] with its meaning, unit, range and default. */
std::string optionsHelp();

/** The program body for core::runProgram. */
int run(const core::CommandLine& cmd);

}  // namespace quasiloc::map_import
