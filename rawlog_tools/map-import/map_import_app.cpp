#include "map_import_app.h"

#include <mrpt/system/CTimeLogger.h>

#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/ini_read.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/map/cloud_export.h>
#include <quasiloc/map/map_import.h>
#include <sstream>

namespace quasiloc::map_import
{
const char* const kUsage = R"(map-import: imports a point cloud with intensities, or a GMMLoc Gaussian-mixture map
(sampled on its components' surfaces), into a quasiloc LidarMap file.

Usage:
  map-import <config.ini> [--set MapImport.key=value]... [--print-timing]
  map-import --input FILE --output FILE.map [--voxel 0.05] [--intensity-scale 0]
             [--format auto|ply|pcd|kitti|xyzi|gmm] [--export FILE.ply|.pcd|.bin|.txt]
             [--export-encoding ascii|binary|binary_big_endian|binary_compressed] [--print-timing]
             [--gmm-density 2500] [--gmm-truncation 2] [--gmm-max-flatness 0.5]
             [--gmm-reflectivity 0.5] [--gmm-seed 1]
  (an .ini given first may be combined with flags; flags override --set, which overrides the file)

Options, section [MapImport]:
  input            the cloud: .ply (ascii / binary little or big endian), .pcd (ascii / binary /
                   binary_compressed), .bin (KITTI velodyne float32 x y z r), .txt .xyz .xyzi .csv .asc
                   ("x y z i" per line, blanks or commas, '#' comments), or .gmm (a GMMLoc
                   Gaussian-mixture map, e.g. data/euroc/maps/gmm/v1.gmm; see below)
  output           the map file: MRPT's binary serialization (gz) of an mrpt::maps::CPointsMapXYZI whose
                   intensity is the reflectivity in [0, 1]
  format           auto (from the extension) | ply | pcd | kitti | xyzi | gmm                 [auto]
  voxel_size_m     > 0: one point per occupied voxel (mean position and reflectivity); 0 = off  [0]
  intensity_scale  > 0: reflectivity = raw / intensity_scale (the raw value meaning full
                   reflectivity, e.g. 255); 0 = automatic rule; must be 0 for .gmm input         [0]
  export_cloud     optional: also write the imported map as a cloud (.ply .pcd .bin .txt)       []
  export_encoding  encoding of export_cloud                                               [binary]
  gmm_density_per_m2    .gmm: surface points per square metre (2500 = 2 cm spacing)        [2500]
  gmm_truncation_sigma  .gmm: ellipse semi-axes in standard deviations                        [2]
  gmm_max_flatness      .gmm: skip components with sigma_min / sigma_mid above this
                        (blobs, not surfaces); 1 = sample every component                    [0.5]
  gmm_reflectivity      .gmm: the constant reflectivity of every point, in [0, 1]            [0.5]
  gmm_seed              .gmm: seed of the sampling jitter (same seed, same map)                [1]

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

namespace
{
std::string lowerCase(std::string s)
{
    for (char& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    return s;
}
}  // namespace

void MapImportOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    MRPT_LOAD_CONFIG_VAR(input, string, cfg, section);
    MRPT_LOAD_CONFIG_VAR(output, string, cfg, section);
    MRPT_LOAD_CONFIG_VAR(format, string, cfg, section);
    // Numbers strictly: MRPT's readers turn "0.1x" into 0.1 and "abc" into 0.
    voxel_size_m = core::readIniDouble(cfg, section, "voxel_size_m", voxel_size_m);
    intensity_scale = core::readIniDouble(cfg, section, "intensity_scale", intensity_scale);
    MRPT_LOAD_CONFIG_VAR(export_cloud, string, cfg, section);
    MRPT_LOAD_CONFIG_VAR(export_encoding, string, cfg, section);
    gmm_density_per_m2 = core::readIniDouble(cfg, section, "gmm_density_per_m2", gmm_density_per_m2);
    gmm_truncation_sigma = core::readIniDouble(cfg, section, "gmm_truncation_sigma", gmm_truncation_sigma);
    gmm_max_flatness = core::readIniDouble(cfg, section, "gmm_max_flatness", gmm_max_flatness);
    gmm_reflectivity = core::readIniDouble(cfg, section, "gmm_reflectivity", gmm_reflectivity);
    const int seed = core::readIniInt(cfg, section, "gmm_seed", static_cast<int>(gmm_seed));
    core::require(seed >= 0, core::iniKeyName(section, "gmm_seed"), "must be >= 0, got " + std::to_string(seed));
    gmm_seed = static_cast<uint64_t>(seed);
}

void MapImportOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    // No name padding (MRPT_SAVE_CONFIG_VAR_COMMENT pads the key, which core::knownKeys would not match),
    // and no comment after an empty value (MRPT would read the comment back as the value).
    auto text = [&](const char* key, const std::string& value, const char* comment) {
        if (value.empty())
            c.write(s, key, value);
        else
            c.write(s, key, value, -1, -1, comment);
    };
    text("input", input, "point cloud to import (.ply .pcd .bin .txt/.xyz/.xyzi/.csv/.asc) or .gmm");
    text("output", output, "LidarMap file to write");
    text("format", format, "auto | ply | pcd | kitti | xyzi | gmm");
    c.write(s, "voxel_size_m", voxel_size_m, -1, -1, "voxel downsampling, 0 = off");
    c.write(s, "intensity_scale", intensity_scale, -1, -1, "reflectivity = raw / intensity_scale; 0 = automatic");
    text("export_cloud", export_cloud, "optional cloud copy of the map (.ply .pcd .bin .txt)");
    text("export_encoding", export_encoding, "ascii | binary | binary_big_endian | binary_compressed");
    c.write(s, "gmm_density_per_m2", gmm_density_per_m2, -1, -1, ".gmm: surface points per m2");
    c.write(s, "gmm_truncation_sigma", gmm_truncation_sigma, -1, -1, ".gmm: ellipse semi-axes in sigmas");
    c.write(s, "gmm_max_flatness", gmm_max_flatness, -1, -1, ".gmm: skip sigma_min/sigma_mid above; 1 = keep all");
    c.write(s, "gmm_reflectivity", gmm_reflectivity, -1, -1, ".gmm: constant reflectivity");
    c.write(s, "gmm_seed", std::to_string(gmm_seed), -1, -1, ".gmm: jitter seed");
}

bool MapImportOptions::gmmInput() const
{
    const std::string f = lowerCase(format);
    return f == "gmm" || (f == "auto" && lowerCase(std::filesystem::path(input).extension().string()) == ".gmm");
}

map::GmmSurfaceOptions MapImportOptions::gmmOptions() const
{
    map::GmmSurfaceOptions g;
    g.density_per_m2 = gmm_density_per_m2;
    g.truncation_sigma = gmm_truncation_sigma;
    g.max_flatness = gmm_max_flatness;
    g.reflectivity = gmm_reflectivity;
    g.seed = gmm_seed;
    return g;
}

void MapImportOptions::check(const std::string& config_name) const
{
    const std::string at = config_name + " [MapImport] ";
    core::require(!input.empty(), at + "input", "is required (or --input FILE)");
    core::require(!output.empty(), at + "output", "is required (or --output FILE.map)");
    core::require(std::filesystem::absolute(input).lexically_normal() !=
                      std::filesystem::absolute(output).lexically_normal(),
                  at + "output", "must differ from the input");
    if (lowerCase(format) != "gmm")
    {
        try
        {
            map::cloudFormatFromString(format, at + "format");
        }
        catch (const core::InputError&)
        {
            throw core::InputError(at + "format", "unknown format '" + format +
                                                      "' (expected auto, ply, pcd, kitti, xyzi or gmm)");
        }
    }
    gmmOptions().check(at + "gmm_");
    core::require(std::isfinite(voxel_size_m) && voxel_size_m >= 0, at + "voxel_size_m", "must be >= 0 (0 = off)");
    core::require(std::isfinite(intensity_scale) && intensity_scale >= 0, at + "intensity_scale",
                  "must be >= 0 (0 = automatic rule)");
    core::require(!gmmInput() || intensity_scale == 0, at + "intensity_scale",
                  "does not apply to .gmm input (a GMM has no intensities; set gmm_reflectivity)");
    const auto encoding = map::cloudEncodingFromString(export_encoding, at + "export_encoding");
    if (!export_cloud.empty())
        map::requireEncodingSupported(map::detectCloudFormat(export_cloud), encoding, at + "export_encoding");
}

namespace
{
/** Splits the plain flags into the optional INI path and [MapImport] overrides. */
std::string applyFlags(const std::vector<std::string>& flags,
                       std::vector<std::pair<std::string, std::string>>& overrides)
{
    static const std::pair<const char*, const char*> kFlagKeys[] = {
        {"--input", "input"},
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

ImportedMap importCloud(const MapImportOptions& opt, const std::string& config_name, mrpt::system::CTimeLogger& timer)
{
    map::ImportOptions io;
    io.format = map::cloudFormatFromString(opt.format, config_name + " [MapImport] format");
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
              << " m2 of ellipses (" << opt.gmm_density_per_m2
              << " points/m2, truncated at " << opt.gmm_truncation_sigma << " sigma, seed " << opt.gmm_seed << ")\n"
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
    const ImportedMap r = opt.gmmInput() ? importGmm(opt, timer) : importCloud(opt, config_name, timer);

    // Every output is staged: they all appear together, or none does.
    core::StagedOutputs staged;
    const std::string ini_path = opt.output + ".ini";
    const std::string map_tmp = staged.addFile(opt.output);
    const std::string ini_tmp = staged.addFile(ini_path);
    timer.enter("save");
    r.map.save(map_tmp);
    if (!opt.export_cloud.empty())
        map::exportCloud(r.map, staged.addFile(opt.export_cloud), map::detectCloudFormat(opt.export_cloud),
                         map::cloudEncodingFromString(opt.export_encoding, "export_encoding"));
    core::writeEffectiveConfig(ini_tmp, {{"MapImport", &opt}}, "map-import effective configuration");
    staged.commit();
    timer.leave("save");

    const double total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cout << "wrote       " << r.map.size() << " points to " << opt.output << " (" << fileSizeText(opt.output)
              << "), effective config " << ini_path << "\n";
    if (!opt.export_cloud.empty())
        std::cout << "exported    " << opt.export_cloud << " (" << opt.export_encoding << ", "
                  << fileSizeText(opt.export_cloud) << ")\n";
    std::cout << "map         " << r.map.summary() << "\n" << std::fixed << std::setprecision(3)
              << "time        read " << timer.getLastTime("import.read") << " s, " << r.second_stage << " "
              << timer.getLastTime("import." + r.second_stage) << " s";
    if (opt.voxel_size_m > 0) std::cout << ", voxel " << timer.getLastTime("import.voxel") << " s";
    std::cout << ", save " << timer.getLastTime("save") << " s, total " << total_s << " s\n";
    if (cmd.print_timing) std::cout << timer.getStatsAsText();
    return 0;
}

}  // namespace quasiloc::map_import
