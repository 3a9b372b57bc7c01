#pragma once
// Options of the quasi-image renderer, INI section [QuasiImage] (every key optional; defaults below).
//
//   [QuasiImage]
//   ; geometry
//   min_depth_m = 0.1                  ; points closer than this (camera z) are ignored
//   max_depth_m = 40                   ; culling range and farthest rendered camera z
//   visibility_block_size_m = 1.0      ; block size of the VisibilityIndex when the renderer builds it
//   ; splatting: each point covers a square of side point_size_m (its footprint at its range, at most
//   ; 2 * max_splat_radius_px + 1 pixels wide) instead of one pixel; set it to the map's point spacing (the
//   ; voxel size) when the camera comes closer than that spacing's pixel footprint, or surfaces fill with holes
//   ; (a 5 cm voxel at 3 m spans 12 px of a 720 px-focal camera). 0 disables it.
//   point_size_m = 0
//   max_splat_radius_px = 6
//   ; see-through filter (a far surface showing through the gaps between a near surface's points): a sparse
//   ; pixel is dropped when the pixels within occlusion_radius_px that are nearer by more than
//   ; occlusion_depth_rel * depth surround it: the largest angle between the directions (from the pixel) of
//   ; consecutive nearer pixels is at most occlusion_max_gap_deg. Beside a nearer surface's edge, or on a
//   ; slanted surface, the nearer pixels lie in a half-plane not containing the pixel: that angle exceeds
//   ; 180 deg, so those pixels are kept. radius 0 disables the filter.
//   occlusion_radius_px = 3
//   occlusion_depth_rel = 0.1
//   occlusion_max_gap_deg = 150
//   ; cross-guided completion of the pixels no point falls on (radius 0 disables it)
//   completion_radius_px = 2           ; square window (2r+1)^2
//   completion_depth_rel = 0.05        ; depth-consistent: |d - d_ref| <= rel * d_ref
//   completion_reflectivity_abs = 0.1  ; reflectivity-consistent: |i - i_p| <= abs (map reflectivity, [0,1])
//   ; scan-line gap filling (after completion): a spinning LiDAR's map is denser along its scan lines than
//   ; across them, so a ground or wall seen from afar renders as stripes of points with empty rows between them,
//   ; and every stripe edge is a false depth and reflectivity edge. A vertical run of at most scanline_gap_px
//   ; empty pixels between two pixels whose depths agree within completion_depth_rel is filled (inverse depth
//   ; and reflectivity interpolated along the column, provenance of the nearer end). 0 disables it.
//   scanline_gap_px = 0
//   ; encoding H = h(I), S = s0, V = b1 + b2 * h(F(D))
//   reflectivity_scope = image         ; image | map: where the normalising percentiles of h(I) come from
//   reflectivity_percentile_low = 2
//   reflectivity_percentile_high = 98
//   hue_low_deg = 240                  ; hue of the low percentile (blue) ...
//   hue_high_deg = 60                  ; ... and of the high percentile (yellow)
//   saturation = 0.8                   ; s0
//   value_base = 0.35                  ; b1
//   value_gain = 0.65                  ; b2 (negative: dark edges); b1 and b1 + b2 must lie in [0, 1]
//   edge_operator = gradient           ; gradient | laplacian: F(D), relative to the pixel's depth
//   edge_scale_rel = 0.1               ; h(F) = min(1, F / edge_scale_rel)
//   gray_mode = luminance              ; luminance | value | shaded_reflectivity (see quasi_image.h)
//   num_threads = 0                    ; 0: OpenCV's thread count (cv::getNumThreads())
#include <mrpt/config/CLoadableOptions.h>

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
    Luminance,           ///< luminance of the BGR quasi-image
    Value,               ///< V alone (depth edges only)
    ShadedReflectivity   ///< V * (0.25 + 0.75 * h(I)): monotonic in reflectivity, with the edges
};

struct QuasiOptions : public mrpt::config::CLoadableOptions
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

    std::string reflectivity_scope = "image";
    double reflectivity_percentile_low = 2.0;
    double reflectivity_percentile_high = 98.0;
    double hue_low_deg = 240.0;
    double hue_high_deg = 60.0;
    double saturation = 0.8;
    double value_base = 0.35;
    double value_gain = 0.65;
    std::string edge_operator = "gradient";
    double edge_scale_rel = 0.1;
    std::string gray_mode = "luminance";
    int num_threads = 0;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
    /** InputError naming `input` and the key for any value that cannot be used. */
    void check(const std::string& input) const;

    ReflectivityScope reflectivityScope() const;
    EdgeOperator edgeOperator() const;
    GrayMode grayMode() const;
};

}  // namespace quasiloc::quasi
