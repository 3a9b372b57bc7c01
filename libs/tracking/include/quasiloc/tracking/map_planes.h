#pragma once
// Map planes for the tracker's point-to-plane factor with an association distribution (the paper's plane
// primitive). Each stereo point of the frame (left camera) is placed in the map at the edge alignment's pose and
// projected into the quasi-image; the map's planes are fitted to the quasi-image's depth in a window at that pixel
// and in windows offset to either side of it. Away from edges they are one plane; near a crease or a contour they
// differ, and the point's association is uncertain: its candidates carry probabilities from its distance to each
// (a Gaussian of its own sigma), which the estimator's reweighting reads (a point that could lie on either of two
// planes constrains the pose less than one that can lie on only one).
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/estimation/measurements.h>
#include <quasiloc/quasi/quasi_image.h>
#include <quasiloc/tracking/pixel_rays.h>
#include <vector>

namespace quasiloc::tracking
{
struct MapPlaneOptions
{
    int window_px = 6;                      ///< half-width of a fitting window (every 2nd pixel is used)
    int offset_px = 8;                      ///< the side windows' offset from the point's pixel
    int min_points = 12;                    ///< valid depth pixels a fit needs
    double max_rms_m = 0.01;                ///< a fit farther from flat is not a plane
    double max_distance_m = 0.1;            ///< a candidate plane farther from the point is not one
    double merge_deg = 10, merge_m = 0.02;  ///< fits closer than this are the same plane
};

class MapPlaneAssociator
{
   public:
    /** `camera`: the quasi-images' pixel geometry. */
    MapPlaneAssociator(const core::CameraModel& camera, const MapPlaneOptions& options);

    /** Plane factors for `points_cam` (left camera frame; sigma_m per point), placed in the map at T_world_cam, against
     *  the completed depth of q (rendered at q.T_world_cam with the same camera). One factor per point with at least
     *  one candidate. */
    std::vector<estimation::PlaneFactorInput> associate(const std::vector<Eigen::Vector3d>& points_cam,
                                                        const std::vector<double>& sigma_m, const quasi::QuasiImage& q,
                                                        const Eigen::Isometry3d& T_world_cam) const;

    /** The plane (world frame, n.p + d = 0) fitted to q's depth in the window centred at (u, v); false when the
     *  window has too few points or is not flat. */
    bool fitPlane(const cv::Mat& depth, const Eigen::Isometry3d& T_world_q, int u, int v, Eigen::Vector3d& n,
                  double& d) const;

   private:
    core::CameraModel camera_;
    MapPlaneOptions options_;
    PixelRays rays_;
};
}  // namespace quasiloc::tracking
