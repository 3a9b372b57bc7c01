#pragma once
// Options of the quasi-image renderer, INI section [QuasiImage] (every key optional). Each key's unit, range, default
// and meaning: QuasiOptions::declare (quasi_options.cpp). Why the stages are as they are:
//  - splatting: each point covers a square of side point_size_m (its footprint at its range, at most
//    2 * max_splat_radius_px + 1 pixels wide) instead of one pixel; set it to the map's point spacing (the voxel
//    size) when the camera comes closer than that spacing's pixel footprint, or surfaces fill with holes (a 5 cm
//    voxel at 3 m spans 12 px of a 720 px-focal camera).
//  - see-through filter (a far surface showing through the gaps between a near surface's points): a sparse pixel is
//    dropped when the pixels within occlusion_radius_px that are nearer by more than occlusion_depth_rel * depth
//    surround it: the largest angle between the directions (from the pixel) of consecutive nearer pixels is at most
//    occlusion_max_gap_deg. Beside a nearer surface's edge, or on a slanted surface, the nearer pixels lie in a
//    half-plane not containing the pixel: that angle exceeds 180 deg, so those pixels are kept.
//  - scan-line gap filling (after completion): a spinning LiDAR's map is denser along its scan lines than across
//    them, so a ground or wall seen from afar renders as stripes of points with empty rows between them, and every
//    stripe edge is a false depth and reflectivity edge. A vertical run of at most scanline_gap_px empty pixels
//    between two pixels whose depths agree within completion_depth_rel is filled (inverse depth and reflectivity
//    interpolated along the column, provenance of the nearer end).
//  - encoding: H = h(I), S = s0, V = b1 + b2 * h(F(D)) (quasi_image.h).
#include <quasiloc/core/declared_options.h>
#include <string>

namespace quasiloc::quasi
{
enum class ReflectivityScope
{
    Image,  ///< percentiles of the valid pixels of each quasi-image (most contrast)
    Map     ///< percentiles of the whole map (same hue for the same point in every view)
};
enum class EdgeOperator
{
    Gradient,  ///< largest relative depth difference to a 4-neighbour: marks depth discontinuities
    Laplacian  ///< largest relative second difference along x or y: also marks creases (wall-floor corners)
};
enum class GrayMode
{
    Luminance,          ///< luminance of the BGR quasi-image
    Value,              ///< V alone (depth edges only)
    ShadedReflectivity  ///< V * (0.25 + 0.75 * h(I)): monotonic in reflectivity, with the edges
};

struct QuasiOptions : public core::DeclaredOptions
{
    double min_depth_m = 0.1;
    double max_depth_m = 40.0;
    double visibility_block_size_m = 1.0;

    double point_size_m = 0.0;
    int max_splat_radius_px = 6;

    int occlusion_radius_px = 3;
    double occlusion_depth_rel = 0.1;
    double occlusion_max_gap_deg = 150.0;

    int completion_radius_px = 2;
    double completion_depth_rel = 0.05;
    double completion_reflectivity_abs = 0.1;
    int scanline_gap_px = 0;

    /** "image" | "map" (reflectivityScope()). Text, not the enum, while code outside this library sets it by name;
     *  loading accepts only the two names. */
    std::string reflectivity_scope = "image";
    double reflectivity_percentile_low = 2.0;
    double reflectivity_percentile_high = 98.0;
    double hue_low_deg = 240.0;
    double hue_high_deg = 60.0;
    double saturation = 0.8;
    double value_base = 0.35;
    double value_gain = 0.65;
    EdgeOperator edge_operator = EdgeOperator::Gradient;
    double edge_scale_rel = 0.1;
    GrayMode gray_mode = GrayMode::Luminance;
    int num_threads = 0;

    void declare(core::OptionTable& t) override;
    /** The declared ranges and the rules between keys: InputError naming `input` and the key. */
    void check(const std::string& input) const;

    ReflectivityScope reflectivityScope() const;
    /** completion_radius_px for a render at 1/downscale of the camera's resolution (QuasiRenderer::render's
     *  per-call radius): the radius is in the camera's pixels, so it fills the same angular gaps there (radius 1
     *  at half resolution: none). */
    int completionRadiusAt(int downscale) const { return completion_radius_px / downscale; }
};

}  // namespace quasiloc::quasi
