#include "map_import_app.h"

#include <mrpt/system/CTimeLogger.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/map/cloud_export.h>
#include <quasiloc/map/surface_thickness.h>
#include <quasiloc/map/map_import.h>
#include <sstream>

namespace quasiloc::map_import
{
const char* const kUsageText = R"(map-import: imports a point cloud with intensities, or a GMMLoc Gaussian-mixture map
(sampled on its components' surfaces), into a quasiloc LidarMap file.

Usage:
  map-import <config.ini> [--set MapImport.key=value]... [--print-timing]
  map-import --input FILE --output FILE.map [--voxel 0.05] [--intensity-scale 0]
             [--format auto|ply|pcd|kitti|xyzi|gmm] [--export FILE.ply|.pcd|.bin|.txt]
             [--export-encoding ascii|binary|binary_big_endian|binary_compressed] [--print-timing]
             [--gmm-density 2500] [--gmm-truncation 2] [--gmm-max-flatness 0.5]
             [--gmm-reflectivity 0.5] [--gmm-seed 1]
  (an .ini given first may be combined with flags; flags override --set, which overrides the file)

OPTIONS
GMM input: each component is taken as a flat patch. Its covariance's two largest principal axes span
an ellipse on the mean with semi-axes gmm_truncation_sigma standard deviations (2 sigma = the extent of
a uniformly filled disc); the ellipse is sampled on a stratified-jittered grid with spacing
1/sqrt(gmm_density_per_m2), so the count is density x area. A GMM carries no intensities: the
reflectivity is the constant gmm_reflectivity. Overlapping components are both sampled (denser there);
voxel_size_m thins them if wanted. GMMLoc's is_degenerated flag is counted, not used.

Reflectivity normalisation, automatic rule (intensity_scale = 0): if all raw intensities are within
[0, 1] they are kept; else if the maximum is <= 255 they are divided by 255; else if the maximum is
<= 65535 they are divided by 65535; else they are divided by the maximum. With either rule, results
outside [0, 1] (negative raw values, values above intensity_scale) are clamped and counted.
The intensity channel is the first property/field named intensity, reflectivity, reflectance,
scalar_intensity, scalar_reflectivity/reflectance, a "scalar field" variant, any other scalar_*, or i.

Outputs: the map file, and the effective configuration beside it as <output>.ini (and export_cloud if
set); all appear only when the import succeeded (nothing is left behind on an error).)";

std::string usage()
{
    std::string text = kUsageText;
    return text.replace(text.find("OPTIONS"), 7, "Options, section [MapImport]:\n" + optionsHelp());
}

namespace
{
/** Splits the plain flags into the optional INI path and [MapImport] overrides. */
std::string applyFlags(const std::vector<std::string>& flags,
                       std::vector<std::pair<std::string, std::string>>& overrides)
{
    static const std::pair<const char*, const char*> kFlagKeys[] = {{"--input", "input"},
                                                                    {"--output", "output"},
                                                                    {"--format", "format"},
                                                                    {"--voxel", "voxel_size_m"},
                                                                    {"--intensity-scale", "intensity_scale"},
                                                                    {"--export", "export_cloud"},
                                                                    {"--export-encoding", "export_encoding"},
                                                                    {"--gmm-density", "gmm_density_per_m2"},
                                                                    {"--gmm-truncation", "gmm_truncation_sigma"},
                                                                    {"--gmm-max-flatness", "gmm_max_flatness"},
                                                                    {"--gmm-reflectivity", "gmm_reflectivity"},
                                                                    {"--gmm-seed", "gmm_seed"}};
    std::string ini;
    for (size_t i = 0; i < flags.size(); ++i)
    {
        const std::string& f = flags[i];
        if (f.rfind("--", 0) != 0)
        {
            core::require(i == 0 && std::filesystem::path(f).extension() == ".ini", "command line (" + f + ")",
                          "unexpected argument (only a first <config.ini> may stand without a flag)");
            ini = f;
            continue;
        }
        const auto eq = f.find('=');
        const std::string name = f.substr(0, eq);
        const char* key = nullptr;
        for (const auto& [flag, k] : kFlagKeys)
            if (name == flag) key = k;
        core::require(key != nullptr, "command line (" + f + ")", "unknown flag (see --help)");
        std::string value;
        if (eq != std::string::npos)
            value = f.substr(eq + 1);
        else
        {
            core::require(i + 1 < flags.size(), "command line (" + f + ")", "needs a value");
            value = flags[++i];
        }
        overrides.emplace_back(std::string("MapImport.") + key, value);
    }
    return ini;
}

/** A CTimeLogger that does not print its table when destroyed (we print it on --print-timing only). */
struct QuietTimeLogger : public mrpt::system::CTimeLogger
{
    QuietTimeLogger() : CTimeLogger(true, "map-import") {}
    ~QuietTimeLogger() override { clear(true); }
};

struct ImportedMap
{
    map::LidarMap map;
    std::string second_stage;  ///< the timed stage after "read": "normalise" or "sample"
};

void printVoxel(const MapImportOptions& opt, size_t before, size_t after)
{
    if (opt.voxel_size_m > 0)
        std::cout << "voxel       " << opt.voxel_size_m << " m: " << before << " -> " << after << " points\n";
}

ImportedMap importCloud(const MapImportOptions& opt, mrpt::system::CTimeLogger& timer)
{
    map::ImportOptions io;
    io.format = opt.cloudFormat();
    io.voxel_size_m = opt.voxel_size_m;
    io.intensity_scale = opt.intensity_scale;
    map::ImportResult r = map::importCloud(opt.input, io, &timer);
    std::cout << "read        " << r.points_read << " points from " << opt.input << " (" << map::toString(r.format)
              << ", " << r.encoding << ", intensity from '" << r.intensity_field << "')\n"
              << "reflectivity " << r.normalisation.rule << "; " << r.normalisation.clamped
              << " values clamped into [0, 1]\n";
    printVoxel(opt, r.points_read, r.map.size());
    return {std::move(r.map), "normalise"};
}

ImportedMap importGmm(const MapImportOptions& opt, mrpt::system::CTimeLogger& timer)
{
    map::GmmImportResult r = map::importGmm(opt.input, opt.gmmOptions(), opt.voxel_size_m, &timer);
    const map::GmmSurfaceStats& st = r.stats;
    std::cout << "read        " << st.components << " Gaussian components from " << opt.input << " (gmm; "
              << st.degenerated << " flagged degenerated by GMMLoc, counted only)\n"
              << "components  " << st.sampled << " sampled, " << st.skipped_not_flat
              << " skipped as not flat (sigma_min / sigma_mid > " << opt.gmm_max_flatness << ")\n"
              << "sampled     " << r.points_sampled << " points on " << std::round(st.area_m2 * 10) / 10
              << " m2 of ellipses (" << opt.gmm_density_per_m2 << " points/m2, truncated at "
              << opt.gmm_truncation_sigma << " sigma, seed " << opt.gmm_seed << ")\n"
              << "reflectivity constant " << opt.gmm_reflectivity << " (a GMM has no intensities)\n";
    printVoxel(opt, r.points_sampled, r.map.size());
    return {std::move(r.map), "sample"};
}

std::string fileSizeText(const std::string& path)
{
    std::ostringstream s;
    s << std::fixed << std::setprecision(2) << std::filesystem::file_size(path) / 1.0e6 << " MB";
    return s.str();
}
}  // namespace

int run(const core::CommandLine& cmd_in)
{
    const auto t0 = std::chrono::steady_clock::now();
    core::CommandLine cmd = cmd_in;
    std::vector<std::pair<std::string, std::string>> flag_overrides;
    cmd.config_path = applyFlags(cmd_in.flags, flag_overrides);
    cmd.overrides.insert(cmd.overrides.end(), flag_overrides.begin(), flag_overrides.end());
    const std::string config_name = cmd.config_path.empty() ? "command line" : cmd.config_path;
    const auto cfg = core::loadConfig(cmd);
    MapImportOptions opt;
    core::loadOptionsChecked(opt, cfg, "MapImport", config_name);
    opt.check(config_name);

    QuietTimeLogger timer;
    const ImportedMap r = opt.gmmInput() ? importGmm(opt, timer) : importCloud(opt, timer);

    // Every output is staged: they all appear together, or none does.
    core::StagedOutputs staged;
    const std::string ini_path = opt.output + ".ini";
    const std::string map_tmp = staged.addFile(opt.output);
    const std::string ini_tmp = staged.addFile(ini_path);
    timer.enter("save");
    r.map.save(map_tmp);
    if (!opt.export_cloud.empty())
        map::exportCloud(r.map, staged.addFile(opt.export_cloud), map::detectCloudFormat(opt.export_cloud),
                         opt.export_encoding);
    core::writeEffectiveConfig(ini_tmp, {{"MapImport", &opt}}, "map-import effective configuration");
    staged.commit();
    timer.leave("save");

    const double total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cout << "wrote       " << r.map.size() << " points to " << opt.output << " (" << fileSizeText(opt.output)
              << "), effective config " << ini_path << "\n";
    if (!opt.export_cloud.empty())
        std::cout << "exported    " << opt.export_cloud << " (" << map::toString(opt.export_encoding) << ", "
                  << fileSizeText(opt.export_cloud) << ")\n";
    std::cout << "map         " << r.map.summary() << "\n"
              << "surfaces    thickness " << map::describe(map::measureSurfaceThickness(r.map)) << "\n"
              << std::fixed << std::setprecision(3) << "time        read " << timer.getLastTime("import.read") << " s, "
              << r.second_stage << " " << timer.getLastTime("import." + r.second_stage) << " s";
    if (opt.voxel_size_m > 0) std::cout << ", voxel " << timer.getLastTime("import.voxel") << " s";
    std::cout << ", save " << timer.getLastTime("save") << " s, total " << total_s << " s\n";
    if (cmd.print_timing) std::cout << timer.getStatsAsText();
    return 0;
}

}  // namespace quasiloc::map_import
