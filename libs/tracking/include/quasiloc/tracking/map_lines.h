#pragma once
// Map lines for the tracker's point-to-line map factor (the paper's L primitive), associated by geometry alone.
//
// Why not by descriptor: camera and quasi-image descriptors do not agree across the modality gap (docs/experiments.md:
// ~0 correct matches on the simulated room and on KITTI). A line of the map's geometry (a crease where two surfaces
// meet, the contour of an object in front of another) is also an edge of the camera image, so with a pose
// estimate the association is a search near the line's projection:
//  1. map side: the quasi-image rendered at the predicted pose, shaded by its surface normals (normalShading:
//     creases become intensity steps, depth discontinuities are marked too), lines detected on it, those without
//     contrast across them dropped (isEdge), and each lifted to the map (lift: along the segment, the foreground
//     pixel next to a depth jump within contour_band_px across it, else the pixel on it; a 3D line by RANSAC);
//  2. camera side: line segments of the camera image;
//  3. association (associateMapLines): every map line whose support projects, at the pose estimate, within
//     window_px of the camera segment's line, within max_angle_deg of its direction and overlapping it, is a
//     candidate; their probabilities follow the projection's distance (a Gaussian of sigma window_px / 3): the
//     association distribution the estimator's reweighting reads. The window comes from the pose covariance.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <memory>
#include <optional>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/estimation/measurements.h>
#include <quasiloc/frontend/lines.h>
#include <quasiloc/tracking/pixel_rays.h>
#include <vector>

namespace quasiloc::tracking
{
struct MapLineOptions
{
    int shading_step = 2;      ///< the shading (and the map side's line detection) at every step-th pixel
    double min_contrast = 16;  ///< mean shading difference across a map segment (grey levels)
    /** Half-width of the band across a segment searched for a depth discontinuity. The shading's normals are
     *  averaged over 9 px, so a contour's segment can sit several pixels inside the foreground; bench_crossmodal's
     *  line profile (simulated frames, 3 px window): the truth associates more segments than a pose one step
     *  away in 31 / 62 / 83 / 80 % of the steps with 4 / 8 / 12 / 16 px. */
    double contour_band_px = 12;
    int samples = 16;            ///< samples along a segment
    double tolerance_m = 0.03;   ///< a support point lies within this of the fitted 3D line
    int min_support = 6;         ///< support points a map line needs
    double min_length_m = 0.15;  ///< 3D extent of the support
    double max_angle_deg = 5;    ///< camera segment vs projected map line
    double min_overlap = 0.3;    ///< shared extent along the camera segment, as a share of the shorter one
    int max_candidates = 3;      ///< per camera segment, nearest first
    double min_probability = 0.05;
};

/** A 3D line of the map: its support points (world) and the fitted line through them. */
struct MapLine
{
    std::vector<Eigen::Vector3d> support_world;
    Eigen::Vector3d point = Eigen::Vector3d::Zero(), direction = Eigen::Vector3d::UnitX();
};

/** The map side for one camera model: its pixel rays are computed once (undistortion is iterative). */
class MapLineExtractor
{
   public:
    /** lines: the detector's options, lengths in image pixels (the shading's detector scales them). */
    MapLineExtractor(const core::CameraModel& camera, const MapLineOptions& options,
                     const frontend::LineOptions& lines);
    ~MapLineExtractor();
    /** The map lines of a completed depth image rendered at T_world_cam: segments detected on its normalShading,
     *  those that are edges (isEdge) lifted (lift). */
    std::vector<MapLine> mapLines(const cv::Mat& depth, const Eigen::Isometry3d& T_world_cam) const;
    /** CV_8U shading of a completed depth image (camera-z metres, 0 invalid; rendered with the camera) by its
     *  surface normals, at every shading_step-th pixel (rows / step x cols / step); 0 where invalid and on the far
     *  side of a depth discontinuity (relative jump > 5 %), so that both creases and contours are intensity steps
     *  at the 3D edge. */
    cv::Mat normalShading(const cv::Mat& depth) const;
    /** True when the shading differs across the segment (in shading pixels) by min_contrast: a crease or a
     *  contour, not a line found in the map's noise on one surface (those lift to 3D lines too). */
    bool isEdge(const cv::Mat& shading, const frontend::LineSegment& segment) const;
    /** The 3D line behind a segment of the image rendered at T_world_cam; nullopt when its support is too small
     *  or too short. */
    std::optional<MapLine> lift(const frontend::LineSegment& segment, const cv::Mat& depth,
                                const Eigen::Isometry3d& T_world_cam) const;

   private:
    MapLineOptions options_;
    PixelRays rays_;
    std::unique_ptr<frontend::LineDetector> shading_detector_;
};

/** One factor input per camera segment with at least one candidate (see the file comment); each candidate keeps
 *  the support points that project onto the camera segment's extent (a distorted image bends long lines), and
 *  each point's sigma is sigma_px * sqrt(n / 2): a segment observes two numbers (offset and angle), however many
 *  points support it. */
std::vector<estimation::LineFactorInput> associateMapLines(const std::vector<frontend::LineSegment>& camera_lines,
                                                           const std::vector<MapLine>& map_lines,
                                                           const core::CameraModel& camera,
                                                           const Eigen::Isometry3d& T_world_cam, double window_px,
                                                           double sigma_px, const MapLineOptions& options);
}  // namespace quasiloc::tracking
