#pragma once
// Lifting quasi-image features to the LiDAR map through per-pixel provenance (quasi_image.h): a keypoint
// becomes the map point whose projection (at the quasi-image's pose, with its camera) is nearest to it; a line
// becomes its LiDAR support, the map points that project onto the segment and lie on one 3D line.
#include <Eigen/Core>
#include <optional>
#include <quasiloc/frontend/association.h>
#include <quasiloc/frontend/lines.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/quasi/quasi_image.h>
#include <vector>

namespace quasiloc::frontend
{
struct LiftedPoint
{
    int map_index = -1;
    Eigen::Vector3f p_world{0, 0, 0};
    float reprojection_px = 0;  ///< distance of the point's projection to the lifted pixel
};

/** Lifts pixel px of the quasi-image: among the pixels within search_radius_px (the pixel itself if 0) with
 *  provenance, the map point projecting nearest to px, if it projects within max(search_radius_px, 1) px.
 *  InputError if the quasi-image and the map do not belong together (provenance index out of range). */
std::optional<LiftedPoint> liftPixel(const quasi::QuasiImage& q, const map::LidarMap& map, const cv::Point2f& px,
                                     double search_radius_px);

struct LineSupport
{
    std::vector<int> map_indices;             ///< support points (distinct)
    std::vector<Eigen::Vector3f> points;      ///< their world positions
    Eigen::Vector3f line_point{0, 0, 0};      ///< the 3D line fitted to them (world frame)
    Eigen::Vector3f line_direction{0, 0, 0};  ///< unit
    bool valid() const { return points.size() >= 2; }
};

/** LiDAR support of a quasi-image segment: per sample along it, the point lifted within line_band_px; then the
 *  largest subset within line_support_tolerance_m of one 3D line (deterministic RANSAC over pairs; a depth
 *  edge mixes foreground and background points, only one of the two stays). */
LineSupport lineSupport(const quasi::QuasiImage& q, const map::LidarMap& map, const LineSegment& segment,
                        const AssociationOptions& options);

}  // namespace quasiloc::frontend
