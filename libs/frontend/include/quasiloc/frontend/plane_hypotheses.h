#pragma once
// Plane hypotheses of a matched map line: on each side of the quasi-image segment, the LiDAR points of a band
// (AssociationOptions plane_side_offset_px .. + plane_side_width_px from the line) are lifted through
// provenance and a plane is fitted (PCA). A fit is rejected when it is degenerate: too few points, support that
// is line-like rather than planar (sqrt(lambda_2 / lambda_1) < plane_min_extent_ratio, where lambda_1 >=
// lambda_2 >= lambda_3 are the scatter's eigenvalues), or support that is not flat (RMS distance to the plane
// > plane_max_rms_m). One hypothesis = one line candidate with all its support (the line's LiDAR support and
// the side planes).
#include <Eigen/Core>
#include <quasiloc/frontend/lifting.h>
#include <vector>

namespace quasiloc::frontend
{
struct PlaneFit
{
    Eigen::Vector3d normal{0, 0, 1};  ///< unit; n . p_world + d = 0
    double d = 0;
    double rms_m = 0;
    double extent_ratio = 0;  ///< sqrt(lambda_2 / lambda_1)
    size_t num_points = 0;
};

enum class PlaneRejection
{
    None,
    TooFewPoints,
    LineLike,
    NotFlat
};

/** PCA plane of `points`; `why` says why it is not usable (None: usable). */
PlaneFit fitPlane(const std::vector<Eigen::Vector3f>& points, const AssociationOptions& options, PlaneRejection& why);

struct PlaneHypothesis
{
    int side = 0;  ///< +1: left of the oriented segment (y down: (d.y, -d.x)), -1: right
    PlaneFit plane;
    std::vector<int> map_indices;  ///< the support the plane was fitted to
};

/** One candidate of a line association, lifted: the map-side segment, its LiDAR support, its planes. */
struct LineHypothesis
{
    int line_index = -1;    ///< map-side (quasi-image) line
    float probability = 0;  ///< p_ic of the association
    LineSupport support;
    std::vector<PlaneHypothesis> planes;  ///< 0, 1 or 2 accepted side planes
};

/** The side planes of a quasi-image segment (0 to 2). */
std::vector<PlaneHypothesis> planeHypotheses(const quasi::QuasiImage& q, const map::LidarMap& map,
                                             const LineSegment& segment, const AssociationOptions& options);

/** Lifts every candidate of a line association (quasi_lines: the map-side segments; InputError for a candidate
 *  index outside them). */
std::vector<LineHypothesis> liftLineAssociation(const Association& association, const quasi::QuasiImage& q,
                                                const map::LidarMap& map, const std::vector<LineSegment>& quasi_lines,
                                                const AssociationOptions& options);

/** liftLineAssociation for every association of one quasi-image, element for element the same result; faster:
 *  a map-side line that is a candidate of several associations is lifted once, and map points near several
 *  segments are projected once. */
std::vector<std::vector<LineHypothesis>> liftLineAssociations(const std::vector<Association>& associations,
                                                              const quasi::QuasiImage& q, const map::LidarMap& map,
                                                              const std::vector<LineSegment>& quasi_lines,
                                                              const AssociationOptions& options);

}  // namespace quasiloc::frontend
