#pragma once
// What a camera image and the LiDAR map share at the true pose, measured per frame:
//  - values: Spearman's rank correlation of the camera's grey level and the map's reflectivity, over the map points
//    projected at the true pose with the nearest one kept per cell_px x cell_px cell (a z-buffer at cell
//    resolution), the grey level read (bilinear) where the point projects; overall, per half of the image (lower,
//    upper) and per surface class;
//  - structure, between the camera image and the quasi-image's reflectivity and depth channels (quasi/quasi_image.h,
//    each channel on its own, log depth), on the pixels where the quasi-image and its whole 5 x 5 neighbourhood are
//    valid, all three smoothed by a Gaussian of blur_sigma_px (the quasi channels by normalised convolution over
//    their valid pixels):
//      orientation agreement = sum w cos(2 (theta_cam - theta_quasi)) / sum w, gradient orientations with the sign
//        ignored (1: parallel, 0: unrelated, -1: perpendicular), w = product of both magnitudes each divided by its
//        90th percentile and capped at 1; chance = the same with the quasi-image's gradients shuffled over the pixels;
//      magnitude correlation = Spearman of the two gradient magnitudes (every second pixel and row); baseline = the
//        camera image shifted by each of `shifts` (the correlation that the spatial layout alone gives);
//      edges = the camera's Canny edges (thresholds: 90th percentile of its gradient magnitude and half of it) within
//        edge_radius_px of a depth discontinuity (Canny on the smoothed log depth, high threshold the larger of its
//        90th percentile and a step of depth_jump) or of a reflectivity edge (Canny on the smoothed reflectivity,
//        percentile thresholds);
//        baseline = the camera's edges shifted by `shifts`; density = share of all compared pixels within
//        edge_radius_px of such a discontinuity (where a random pixel would land).
#include <array>
#include <opencv2/core.hpp>
#include <quasiloc/quasi/quasi_renderer.h>
#include <quasiloc/sim/surface_class.h>
#include <string>
#include <vector>

#include "kitti_sequence.h"

namespace quasiloc::bench
{
struct ModalityOptions
{
    int cell_px = 4;
    double min_depth_m = 0.3;
    double max_depth_m = 60;
    size_t min_points = 30;  ///< fewer points of a class in a frame: no correlation for it (NaN)
    double blur_sigma_px = 1.0;
    double depth_jump = 0.15;
    double edge_radius_px = 2.0;
    /** Diagonal: a shift along an edge's own direction would keep it aligned. */
    std::vector<cv::Point> shifts = {{20, 10}, {-20, 10}, {20, -10}, {-20, -10}};
};

constexpr int kClasses = sim::kNumSurfaceClasses;

struct FrameModalityStats
{
    double grey_refl_all = NAN;
    double grey_refl_lower = NAN, grey_refl_upper = NAN;  ///< pairs in the lower / upper half of the image
    std::array<double, kClasses> grey_refl_class{};
    size_t points_all = 0;
    std::array<size_t, kClasses> points_class{};

    double valid_fraction = 0;  ///< of the image, pixels compared for structure
    double orient_refl = NAN, orient_refl_chance = NAN, orient_depth = NAN, orient_depth_chance = NAN;
    double magnitude_refl = NAN, magnitude_refl_shifted = NAN, magnitude_depth = NAN, magnitude_depth_shifted = NAN;
    size_t camera_edges = 0;
    double edges_depth = NAN, edges_depth_shifted = NAN, depth_density = NAN;
    double edges_refl = NAN, edges_refl_shifted = NAN, refl_density = NAN;
};

/** The statistics of one frame; `labels` holds one sim::SurfaceClass per map point (map order). */
FrameModalityStats measureFrame(const QueryFrame& frame, const core::CameraModel& camera, const map::LidarMap& map,
                                const std::vector<uint8_t>& labels, quasi::QuasiRenderer& renderer,
                                const ModalityOptions& options, uint32_t seed);

/** The frame with the map points of the z-buffered cells drawn in their class colours (left), beside the camera
 *  edges (red), the quasi-image's depth discontinuities (green) and reflectivity edges (blue) (right). */
void writeClassOverlay(const std::string& path, const QueryFrame& frame, const core::CameraModel& camera,
                       const map::LidarMap& map, const std::vector<uint8_t>& labels, quasi::QuasiRenderer& renderer,
                       const ModalityOptions& options);

/** The grey/reflectivity pairs of a frame as CSV (u, v, depth_m, grey, reflectivity, class, point index). */
void writePairsCsv(const std::string& path, const QueryFrame& frame, const core::CameraModel& camera,
                   const map::LidarMap& map, const std::vector<uint8_t>& labels, const ModalityOptions& options);

/** BGR colour of a class in the overlays (road grey, marking white, facade orange, vegetation green, vehicle
 *  magenta, other cyan). */
cv::Scalar classColour(int surface_class);

}  // namespace quasiloc::bench
