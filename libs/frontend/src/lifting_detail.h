#pragma once
// Pieces of lifting.cpp shared with plane_hypotheses.cpp and the equivalence tests (not part of the public
// interface).
//
// PixelLifter: the search behind liftPixel (lifting.h), made cheap for callers that lift many pixels of one
// quasi-image (line support lifts 16 samples per segment, each over a (2r+1)^2 window): the pose is inverted
// once, and a map point is projected once however many window pixels show it (completed pixels repeat the point
// of their nearest sparse pixel, and the windows of neighbouring samples overlap). Results are exactly those of
// the plain search: same candidates, same distances (std::hypot), same tie-breaking (first pixel in row order).
#include <mrpt/poses/CPose3D.h>

#include <optional>
#include <quasiloc/frontend/lifting.h>
#include <vector>

namespace quasiloc::frontend::detail
{
class PixelLifter
{
   public:
    /** cache_slots (0, or a power of two): 256 serve one segment's samples; lifting many segments of the image
     *  through one lifter shares the projections of the points near several of them; 0 (one pixel to lift, as
     *  liftPixel): no cache, the window's repeated points are skipped all the same. */
    PixelLifter(const quasi::QuasiImage& q, const map::LidarMap& map, size_t cache_slots = 256);
    /** liftPixel(q, map, px, search_radius_px). */
    std::optional<LiftedPoint> lift(const cv::Point2f& px, double search_radius_px);

   private:
    /** Pixel of map point idx at the quasi-image's pose; false if it does not project. */
    bool project(int idx, double& u, double& v);

    struct Projection
    {
        int idx = -1;  ///< -1: empty slot
        bool ok = false;
        double u = 0, v = 0;
    };
    const quasi::QuasiImage& q_;
    const map::LidarMap& map_;
    mrpt::poses::CPose3D T_cam_world_;
    // Direct-mapped by index: a collision only costs a projection again.
    std::vector<Projection> cache_;
};

/** Largest subset of `pts` within tol of the line through two of them (all pairs when few, else a fixed stride
 *  over pairs: deterministic; the first pair with the largest count wins). Returns the inlier flags, and the line
 *  refined on the inliers (centroid c, principal direction d). */
std::vector<char> fitLine3d(const std::vector<Eigen::Vector3f>& pts, float tol, Eigen::Vector3f& c, Eigen::Vector3f& d);

/** lineSupport (lifting.h) through a lifter of the segment's quasi-image. */
LineSupport lineSupport(PixelLifter& lifter, const LineSegment& segment, const AssociationOptions& options);

}  // namespace quasiloc::frontend::detail
