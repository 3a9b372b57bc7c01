#include <mrpt/config/CConfigFileBase.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <quasiloc/core/error.h>
#include <quasiloc/quasi/quasi_options.h>

namespace quasiloc::quasi
{
namespace
{
// MRPT's read_double/read_int turn "abc" into 0; a typo in an INI value must be an error instead.
std::string keyName(const std::string& section, const std::string& key) { return "[" + section + "] " + key; }

double readDouble(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
                  double def)
{
    const std::string s = cfg.read_string(section, key, "", false);
    if (s.empty()) return def;
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(s.c_str(), &end);
    while (end && (*end == ' ' || *end == '\t')) ++end;
    if (errno != 0 || end == s.c_str() || *end != '\0' || !std::isfinite(v))
        throw core::InputError(keyName(section, key), "'" + s + "' is not a finite number");
    return v;
}

int readInt(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key, int def)
{
    const double v = readDouble(cfg, section, key, def);
    if (v != std::floor(v) || std::abs(v) > 1e9)
        throw core::InputError(keyName(section, key), std::to_string(v) + " is not an integer");
    return static_cast<int>(v);
}
}  // namespace

void QuasiOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    min_depth_m = readDouble(cfg, s, "min_depth_m", min_depth_m);
    max_depth_m = readDouble(cfg, s, "max_depth_m", max_depth_m);
    visibility_block_size_m = readDouble(cfg, s, "visibility_block_size_m", visibility_block_size_m);
    point_size_m = readDouble(cfg, s, "point_size_m", point_size_m);
    max_splat_radius_px = readInt(cfg, s, "max_splat_radius_px", max_splat_radius_px);
    occlusion_radius_px = readInt(cfg, s, "occlusion_radius_px", occlusion_radius_px);
    occlusion_depth_rel = readDouble(cfg, s, "occlusion_depth_rel", occlusion_depth_rel);
    occlusion_max_gap_deg = readDouble(cfg, s, "occlusion_max_gap_deg", occlusion_max_gap_deg);
    completion_radius_px = readInt(cfg, s, "completion_radius_px", completion_radius_px);
    completion_depth_rel = readDouble(cfg, s, "completion_depth_rel", completion_depth_rel);
    completion_reflectivity_abs = readDouble(cfg, s, "completion_reflectivity_abs", completion_reflectivity_abs);
    scanline_gap_px = readInt(cfg, s, "scanline_gap_px", scanline_gap_px);
    reflectivity_scope = cfg.read_string(s, "reflectivity_scope", reflectivity_scope);
    reflectivity_percentile_low = readDouble(cfg, s, "reflectivity_percentile_low", reflectivity_percentile_low);
    reflectivity_percentile_high = readDouble(cfg, s, "reflectivity_percentile_high", reflectivity_percentile_high);
    hue_low_deg = readDouble(cfg, s, "hue_low_deg", hue_low_deg);
    hue_high_deg = readDouble(cfg, s, "hue_high_deg", hue_high_deg);
    saturation = readDouble(cfg, s, "saturation", saturation);
    value_base = readDouble(cfg, s, "value_base", value_base);
    value_gain = readDouble(cfg, s, "value_gain", value_gain);
    edge_operator = cfg.read_string(s, "edge_operator", edge_operator);
    edge_scale_rel = readDouble(cfg, s, "edge_scale_rel", edge_scale_rel);
    gray_mode = cfg.read_string(s, "gray_mode", gray_mode);
    num_threads = readInt(cfg, s, "num_threads", num_threads);
}

void QuasiOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    c.write(s, "min_depth_m", min_depth_m, 30, 40, "points nearer than this (camera z) are ignored");
    c.write(s, "max_depth_m", max_depth_m, 30, 40, "culling range and farthest rendered camera z");
    c.write(s, "visibility_block_size_m", visibility_block_size_m, 30, 40, "VisibilityIndex block size");
    c.write(s, "point_size_m", point_size_m, 30, 40, "splat footprint of a point; 0: one pixel");
    c.write(s, "max_splat_radius_px", max_splat_radius_px, 30, 40, "largest splat half-width");
    c.write(s, "occlusion_radius_px", occlusion_radius_px, 30, 40, "see-through filter window; 0: off");
    c.write(s, "occlusion_depth_rel", occlusion_depth_rel, 30, 40, "nearer by more than rel*depth occludes");
    c.write(s, "occlusion_max_gap_deg", occlusion_max_gap_deg, 30, 40, "largest angle between nearer pixels: surrounded");
    c.write(s, "completion_radius_px", completion_radius_px, 30, 40, "completion window (2r+1)^2; 0: off");
    c.write(s, "completion_depth_rel", completion_depth_rel, 30, 40, "|d - d_ref| <= rel*d_ref");
    c.write(s, "completion_reflectivity_abs", completion_reflectivity_abs, 30, 40, "|i - i_p| <= abs");
    c.write(s, "scanline_gap_px", scanline_gap_px, 30, 40, "longest vertical gap filled between scan lines; 0: off");
    c.write(s, "reflectivity_scope", reflectivity_scope, 30, 40, "image | map (percentiles of h(I))");
    c.write(s, "reflectivity_percentile_low", reflectivity_percentile_low, 30, 40, "percent");
    c.write(s, "reflectivity_percentile_high", reflectivity_percentile_high, 30, 40, "percent");
    c.write(s, "hue_low_deg", hue_low_deg, 30, 40, "hue of the low reflectivity percentile");
    c.write(s, "hue_high_deg", hue_high_deg, 30, 40, "hue of the high reflectivity percentile");
    c.write(s, "saturation", saturation, 30, 40, "s0, 0..1");
    c.write(s, "value_base", value_base, 30, 40, "b1 of V = b1 + b2*h(F(D))");
    c.write(s, "value_gain", value_gain, 30, 40, "b2 of V = b1 + b2*h(F(D))");
    c.write(s, "edge_operator", edge_operator, 30, 40, "gradient | laplacian");
    c.write(s, "edge_scale_rel", edge_scale_rel, 30, 40, "h(F) = min(1, F/edge_scale_rel)");
    c.write(s, "gray_mode", gray_mode, 30, 40, "luminance | value | shaded_reflectivity");
    c.write(s, "num_threads", num_threads, 30, 40, "0: OpenCV's thread count");
}

void QuasiOptions::check(const std::string& input) const
{
    auto key = [&](const char* k) { return input + " [QuasiImage] " + k; };
    core::require(min_depth_m > 0, key("min_depth_m"), "must be > 0");
    core::require(max_depth_m > min_depth_m, key("max_depth_m"), "must be > min_depth_m");
    core::require(visibility_block_size_m > 0, key("visibility_block_size_m"), "must be > 0");
    core::require(point_size_m >= 0, key("point_size_m"), "must be >= 0");
    core::require(max_splat_radius_px >= 0 && max_splat_radius_px <= 32, key("max_splat_radius_px"),
                  "must be 0..32");
    core::require(occlusion_radius_px >= 0 && occlusion_radius_px <= 15, key("occlusion_radius_px"),
                  "must be 0..15");
    core::require(occlusion_depth_rel > 0, key("occlusion_depth_rel"), "must be > 0");
    core::require(occlusion_max_gap_deg > 0 && occlusion_max_gap_deg < 180, key("occlusion_max_gap_deg"),
                  "must be in (0, 180) (from 180 on, pixels beside a nearer edge would count as surrounded)");
    core::require(completion_radius_px >= 0 && completion_radius_px <= 15, key("completion_radius_px"),
                  "must be 0..15");
    core::require(completion_depth_rel > 0, key("completion_depth_rel"), "must be > 0");
    core::require(completion_reflectivity_abs >= 0, key("completion_reflectivity_abs"), "must be >= 0");
    core::require(scanline_gap_px >= 0 && scanline_gap_px <= 64, key("scanline_gap_px"), "must be 0..64");
    reflectivityScope();
    edgeOperator();
    grayMode();
    core::require(reflectivity_percentile_low >= 0 && reflectivity_percentile_low < reflectivity_percentile_high &&
                      reflectivity_percentile_high <= 100,
                  key("reflectivity_percentile_low/high"), "need 0 <= low < high <= 100");
    core::require(hue_low_deg >= 0 && hue_low_deg <= 360, key("hue_low_deg"), "must be 0..360");
    core::require(hue_high_deg >= 0 && hue_high_deg <= 360, key("hue_high_deg"), "must be 0..360");
    core::require(saturation >= 0 && saturation <= 1, key("saturation"), "must be 0..1");
    core::require(value_base >= 0 && value_base <= 1, key("value_base"), "must be 0..1");
    core::require(value_base + value_gain >= 0 && value_base + value_gain <= 1, key("value_gain"),
                  "value_base + value_gain must be 0..1");
    core::require(edge_scale_rel > 0, key("edge_scale_rel"), "must be > 0");
    core::require(num_threads >= 0 && num_threads <= 256, key("num_threads"), "must be 0..256");
}

ReflectivityScope QuasiOptions::reflectivityScope() const
{
    if (reflectivity_scope == "image") return ReflectivityScope::Image;
    if (reflectivity_scope == "map") return ReflectivityScope::Map;
    throw core::InputError("[QuasiImage] reflectivity_scope", "'" + reflectivity_scope + "' (expected image or map)");
}

EdgeOperator QuasiOptions::edgeOperator() const
{
    if (edge_operator == "gradient") return EdgeOperator::Gradient;
    if (edge_operator == "laplacian") return EdgeOperator::Laplacian;
    throw core::InputError("[QuasiImage] edge_operator", "'" + edge_operator + "' (expected gradient or laplacian)");
}

GrayMode QuasiOptions::grayMode() const
{
    if (gray_mode == "luminance") return GrayMode::Luminance;
    if (gray_mode == "value") return GrayMode::Value;
    if (gray_mode == "shaded_reflectivity") return GrayMode::ShadedReflectivity;
    throw core::InputError("[QuasiImage] gray_mode",
                           "'" + gray_mode + "' (expected luminance, value or shaded_reflectivity)");
}

}  // namespace quasiloc::quasi
