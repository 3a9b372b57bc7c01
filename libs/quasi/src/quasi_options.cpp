// The keys of [QuasiImage], each declared once (name, member, unit, range, meaning), and the rules between keys.
#include <quasiloc/core/error.h>
#include <quasiloc/quasi/quasi_options.h>

namespace quasiloc::quasi
{
using core::Range;

namespace
{
void declareRendering(QuasiOptions& o, core::OptionTable& t)
{
    t.add("min_depth_m", o.min_depth_m, "m", Range::above(0), "points nearer than this (camera z) are ignored");
    t.add("max_depth_m", o.max_depth_m, "m", Range::above(0),
          "culling range and farthest rendered camera z (> min_depth_m)");
    t.add("visibility_block_size_m", o.visibility_block_size_m, "m", Range::above(0),
          "block size of the VisibilityIndex when the renderer builds it");
    t.add("point_size_m", o.point_size_m, "m", Range::atLeast(0), "splat footprint of a point; 0 = one pixel");
    t.add("max_splat_radius_px", o.max_splat_radius_px, "px", Range::between(0, 32), "largest splat half-width");
    t.add("occlusion_radius_px", o.occlusion_radius_px, "px", Range::between(0, 15),
          "see-through filter window; 0 = off");
    t.add("occlusion_depth_rel", o.occlusion_depth_rel, "", Range::above(0),
          "a pixel nearer by more than rel * depth occludes");
    t.add("occlusion_max_gap_deg", o.occlusion_max_gap_deg, "deg", Range::strictlyBetween(0, 180),
          "largest angle between consecutive nearer pixels that still surrounds (from 180 on, an edge would)");
    t.add("completion_radius_px", o.completion_radius_px, "px", Range::between(0, 15),
          "cross-guided completion window (2r+1)^2; 0 = off");
    t.add("completion_depth_rel", o.completion_depth_rel, "", Range::above(0),
          "depth-consistent: |d - d_ref| <= rel * d_ref");
    t.add("completion_reflectivity_abs", o.completion_reflectivity_abs, "", Range::atLeast(0),
          "reflectivity-consistent: |i - i_p| <= abs (map reflectivity, [0,1])");
    t.add("scanline_gap_px", o.scanline_gap_px, "px", Range::between(0, 64),
          "longest vertical gap filled between scan lines; 0 = off");
}

void declareEncoding(QuasiOptions& o, core::OptionTable& t)
{
    // The scope is text (quasi_options.h); each name maps to itself, so loading still rejects any other.
    t.addEnum<std::string>("reflectivity_scope", o.reflectivity_scope, {{"image", "image"}, {"map", "map"}},
                           "where the normalising percentiles of h(I) come from: each image, or the whole map");
    t.add("reflectivity_percentile_low", o.reflectivity_percentile_low, "%", Range::between(0, 100),
          "reflectivity mapped to hue_low_deg (< reflectivity_percentile_high)");
    t.add("reflectivity_percentile_high", o.reflectivity_percentile_high, "%", Range::between(0, 100),
          "reflectivity mapped to hue_high_deg");
    t.add("hue_low_deg", o.hue_low_deg, "deg", Range::between(0, 360), "hue of the low percentile (blue)");
    t.add("hue_high_deg", o.hue_high_deg, "deg", Range::between(0, 360), "hue of the high percentile (yellow)");
    t.add("saturation", o.saturation, "", Range::between(0, 1), "s0");
    t.add("value_base", o.value_base, "", Range::between(0, 1), "b1 of V = b1 + b2 * h(F(D))");
    t.add("value_gain", o.value_gain, "", Range::between(-1, 1),
          "b2 of V = b1 + b2 * h(F(D)) (negative: dark edges); b1 + b2 must lie in [0, 1]");
    t.addEnum("edge_operator", o.edge_operator,
              {{"gradient", EdgeOperator::Gradient}, {"laplacian", EdgeOperator::Laplacian}},
              "F(D), relative to the pixel's depth: depth steps (gradient) or also creases (laplacian)");
    t.add("edge_scale_rel", o.edge_scale_rel, "", Range::above(0), "h(F) = min(1, F / edge_scale_rel)");
    t.addEnum("gray_mode", o.gray_mode,
              {{"luminance", GrayMode::Luminance},
               {"value", GrayMode::Value},
               {"shaded_reflectivity", GrayMode::ShadedReflectivity}},
              "what the grayscale front-end sees (quasi_image.h)");
    t.add("num_threads", o.num_threads, "", Range::between(0, 256), "0 = OpenCV's thread count (cv::getNumThreads())");
}
}  // namespace

void QuasiOptions::declare(core::OptionTable& t)
{
    declareRendering(*this, t);
    declareEncoding(*this, t);
}

void QuasiOptions::check(const std::string& input) const
{
    const std::string section = input + " [QuasiImage]";
    checkRanges(section);
    core::require(max_depth_m > min_depth_m, section + " max_depth_m", "must be > min_depth_m");
    core::require(reflectivity_percentile_low < reflectivity_percentile_high,
                  section + " reflectivity_percentile_low/high", "need 0 <= low < high <= 100");
    core::require(value_base + value_gain >= 0 && value_base + value_gain <= 1, section + " value_gain",
                  "value_base + value_gain must be 0..1");
    reflectivityScope();
}

ReflectivityScope QuasiOptions::reflectivityScope() const
{
    if (reflectivity_scope == "image") return ReflectivityScope::Image;
    if (reflectivity_scope == "map") return ReflectivityScope::Map;
    throw core::InputError("[QuasiImage] reflectivity_scope", "'" + reflectivity_scope + "' (expected image or map)");
}

}  // namespace quasiloc::quasi
