// The keys of [MapImport], each declared once (name, member, unit, range, meaning), and the rules between keys.
#include <cctype>
#include <filesystem>
#include <quasiloc/core/error.h>
#include <quasiloc/map/map_import.h>

#include "map_import_app.h"

namespace quasiloc::map_import
{
using core::Range;

namespace
{
std::string lowerCase(std::string s)
{
    for (char& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    return s;
}
}  // namespace

void MapImportOptions::declare(core::OptionTable& t)
{
    t.add("input", input, "the cloud (.ply .pcd .bin .txt .xyz .xyzi .csv .asc) or a GMMLoc .gmm map (see below)");
    t.add("output", output,
          "the LidarMap file: MRPT's serialization (gz) of a CPointsMapXYZI, intensity = reflectivity in [0, 1]");
    // bin, txt and text: other names of kitti and xyzi, accepted as before.
    t.addEnum("format", format,
              {{"auto", InputFormat::Auto},
               {"ply", InputFormat::Ply},
               {"pcd", InputFormat::Pcd},
               {"kitti", InputFormat::Kitti},
               {"xyzi", InputFormat::Xyzi},
               {"gmm", InputFormat::Gmm},
               {"bin", InputFormat::Kitti},
               {"txt", InputFormat::Xyzi},
               {"text", InputFormat::Xyzi}},
              "the input's format; auto = from the extension");
    t.add("voxel_size_m", voxel_size_m, "m", Range::atLeast(0),
          "> 0: one point per occupied voxel (mean position and reflectivity); 0 = off");
    t.add("intensity_scale", intensity_scale, "", Range::atLeast(0),
          "> 0: reflectivity = raw / intensity_scale (e.g. 255); 0 = automatic rule; must be 0 for .gmm input");
    t.add("export_cloud", export_cloud, "optional: also write the imported map as a cloud (.ply .pcd .bin .txt)");
    t.addEnum("export_encoding", export_encoding,
              {{"ascii", map::CloudEncoding::Ascii},
               {"binary", map::CloudEncoding::Binary},
               {"binary_big_endian", map::CloudEncoding::BinaryBigEndian},
               {"binary_compressed", map::CloudEncoding::BinaryCompressed},
               {"binary_little_endian", map::CloudEncoding::Binary}},
              "encoding of export_cloud (PLY: no binary_compressed; PCD: no binary_big_endian)");
    // The ranges of map::GmmSurfaceOptions::check.
    t.add("gmm_density_per_m2", gmm_density_per_m2, "1/m^2", Range::between(1, 1e6),
          ".gmm: surface points per square metre (2500 = 2 cm spacing)");
    t.add("gmm_truncation_sigma", gmm_truncation_sigma, "", Range::between(0.1, 5),
          ".gmm: ellipse semi-axes in standard deviations");
    t.add("gmm_max_flatness", gmm_max_flatness, "", Range::between(0, 1),
          ".gmm: skip components with sigma_min / sigma_mid above this (blobs, not surfaces); 1 = sample all");
    t.add("gmm_reflectivity", gmm_reflectivity, "", Range::between(0, 1),
          ".gmm: the constant reflectivity of every point (a GMM has none)");
    t.add("gmm_seed", gmm_seed, "", Range::between(0, 1e9), ".gmm: seed of the sampling jitter (same seed, same map)");
}

bool MapImportOptions::gmmInput() const
{
    return format == InputFormat::Gmm ||
           (format == InputFormat::Auto && lowerCase(std::filesystem::path(input).extension().string()) == ".gmm");
}

map::CloudFormat MapImportOptions::cloudFormat() const
{
    switch (format)
    {
        case InputFormat::Ply: return map::CloudFormat::Ply;
        case InputFormat::Pcd: return map::CloudFormat::Pcd;
        case InputFormat::Kitti: return map::CloudFormat::KittiBin;
        case InputFormat::Xyzi: return map::CloudFormat::Xyzi;
        default: return map::CloudFormat::Auto;
    }
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
    checkRanges(config_name + " [MapImport]");
    core::require(!input.empty(), at + "input", "is required (or --input FILE)");
    core::require(!output.empty(), at + "output", "is required (or --output FILE.map)");
    core::require(
        std::filesystem::absolute(input).lexically_normal() != std::filesystem::absolute(output).lexically_normal(),
        at + "output", "must differ from the input");
    core::require(!gmmInput() || intensity_scale == 0, at + "intensity_scale",
                  "does not apply to .gmm input (a GMM has no intensities; set gmm_reflectivity)");
    if (!export_cloud.empty())
        map::requireEncodingSupported(map::detectCloudFormat(export_cloud), export_encoding, at + "export_encoding");
}

std::string optionsHelp()
{
    std::string text;
    for (const core::OptionDescription& d : MapImportOptions().describe())
    {
        std::string line = "  " + d.key + std::string(d.key.size() < 22 ? 22 - d.key.size() : 1, ' ') + d.doc;
        if (!d.unit.empty()) line += " [" + d.unit + "]";
        text += line + "\n" + std::string(24, ' ') + (d.range.empty() ? "" : d.range + "; ") + "default " +
                (d.default_value.empty() ? "(empty)" : d.default_value) + "\n";
    }
    return text;
}

}  // namespace quasiloc::map_import
