#include <quasiloc/core/error.h>
#include <quasiloc/estimation/direct_alignment.h>

#include <quasiloc/core/ini_read.h>

namespace quasiloc::estimation
{
void DirectAlignmentOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    pyramid_levels = core::readIniInt(cfg, s, "pyramid_levels", pyramid_levels);
    camera_blur_sigma_px = core::readIniDouble(cfg, s, "camera_blur_sigma_px", camera_blur_sigma_px);
    canny_high_percentile = core::readIniDouble(cfg, s, "canny_high_percentile", canny_high_percentile);
    canny_low_ratio = core::readIniDouble(cfg, s, "canny_low_ratio", canny_low_ratio);
    orientation_bins = core::readIniInt(cfg, s, "orientation_bins", orientation_bins);
    truncation_px = core::readIniDouble(cfg, s, "truncation_px", truncation_px);
    huber_px = core::readIniDouble(cfg, s, "huber_px", huber_px);
    iterations_per_level = core::readIniInt(cfg, s, "iterations_per_level", iterations_per_level);
    max_edge_points = core::readIniInt(cfg, s, "max_edge_points", max_edge_points);
    model_block_px = core::readIniInt(cfg, s, "model_block_px", model_block_px);
    model_close_px = core::readIniInt(cfg, s, "model_close_px", model_close_px);
    depth_edge_rel = core::readIniDouble(cfg, s, "depth_edge_rel", depth_edge_rel);
    refl_canny_high = core::readIniDouble(cfg, s, "refl_canny_high", refl_canny_high);
    use_reflectivity_edges = core::readIniBool(cfg, s, "use_reflectivity_edges", use_reflectivity_edges);
    nmi_bins = core::readIniInt(cfg, s, "nmi_bins", nmi_bins);
    max_nmi_points = core::readIniInt(cfg, s, "max_nmi_points", max_nmi_points);
}

void DirectAlignmentOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    c.write(s, "pyramid_levels", pyramid_levels, 28, 10, "level l: 1/2^l resolution");
    c.write(s, "camera_blur_sigma_px", camera_blur_sigma_px, 28, 10, "blur before the camera Canny (level px)");
    c.write(s, "canny_high_percentile", canny_high_percentile, 28, 10, "camera Canny high threshold percentile");
    c.write(s, "canny_low_ratio", canny_low_ratio, 28, 10, "low = ratio * high");
    c.write(s, "orientation_bins", orientation_bins, 28, 10, "edge orientation classes (1: none)");
    c.write(s, "truncation_px", truncation_px, 28, 10, "distance transform truncation (level px)");
    c.write(s, "huber_px", huber_px, 28, 10, "Huber threshold (level px)");
    c.write(s, "iterations_per_level", iterations_per_level, 28, 10);
    c.write(s, "max_edge_points", max_edge_points, 28, 10);
    c.write(s, "model_block_px", model_block_px, 28, 10, "edges on planes reduced by this block size");
    c.write(s, "model_close_px", model_close_px, 28, 10, "inverse-depth closing radius (blocks)");
    c.write(s, "depth_edge_rel", depth_edge_rel, 28, 10, "depth edge: neighbour farther by rel * depth");
    c.write(s, "refl_canny_high", refl_canny_high, 28, 10, "reflectivity Canny high threshold ([0,1])");
    c.write(s, "use_reflectivity_edges", use_reflectivity_edges ? "true" : "false", 28, 10);
    c.write(s, "nmi_bins", nmi_bins, 28, 10);
    c.write(s, "max_nmi_points", max_nmi_points, 28, 10);
}

void DirectAlignmentOptions::check(const std::string& input) const
{
    const std::string k = input + ": [DirectAlignment] ";
    core::require(pyramid_levels >= 0 && pyramid_levels <= 6, k + "pyramid_levels", "must be in [0, 6]");
    core::require(camera_blur_sigma_px >= 0 && camera_blur_sigma_px <= 20, k + "camera_blur_sigma_px", "must be in [0, 20]");
    core::require(canny_high_percentile > 0 && canny_high_percentile < 100, k + "canny_high_percentile",
                  "must be in (0, 100)");
    core::require(canny_low_ratio > 0 && canny_low_ratio <= 1, k + "canny_low_ratio", "must be in (0, 1]");
    core::require(orientation_bins >= 1 && orientation_bins <= 16, k + "orientation_bins", "must be in [1, 16]");
    core::require(truncation_px >= 1 && truncation_px <= 200, k + "truncation_px", "must be in [1, 200]");
    core::require(huber_px > 0, k + "huber_px", "must be > 0");
    core::require(iterations_per_level >= 1 && iterations_per_level <= 200, k + "iterations_per_level",
                  "must be in [1, 200]");
    core::require(max_edge_points >= 20, k + "max_edge_points", "must be >= 20");
    core::require(model_block_px >= 1 && model_block_px <= 16, k + "model_block_px", "must be in [1, 16]");
    core::require(model_close_px >= 0 && model_close_px <= 8, k + "model_close_px", "must be in [0, 8]");
    core::require(depth_edge_rel > 0, k + "depth_edge_rel", "must be > 0");
    core::require(refl_canny_high > 0 && refl_canny_high <= 1, k + "refl_canny_high", "must be in (0, 1]");
    core::require(nmi_bins >= 4 && nmi_bins <= 256, k + "nmi_bins", "must be in [4, 256]");
    core::require(max_nmi_points >= 50, k + "max_nmi_points", "must be >= 50");
}

}  // namespace quasiloc::estimation
