#pragma once
// How much the map edge term of one keyframe is trusted: the term pulls the pose toward the optimum of the map's
// reflectivity edges, which on a noisy or changed map is not where the stereo geometry puts the camera. The test is
// a single step, in the stereo surface term's own units: the frame's stereo points are measured against the map's
// surfaces (distance field) at the prediction (the IMU carrying the last window, which holds the stereo and landmark
// terms) and at the edge term's optimum (the direct alignment's pose). The surface term's cost there,
//     chi2(T) = effective_points x mean over the points of (min(distance, truncation) / sigma)^2
// (the window's MapDistanceTerm: every point's sigma scaled so that all count as effective_points observations),
// grows by chi2(edges) - chi2(prediction) when the edge optimum moves the camera off the surfaces the stereo sees;
// its square root is the disagreement in sigmas. The edge term's weight is then
//     w = exp(-(disagreement / scale)^2 / 2)   (1 when the edge optimum fits the stereo at least as well),
// applied by dividing its pixel sigma by sqrt(w); below kEdgeTrustDropWeight the term is left out for the frame.
// Scale: [MapFactors] edge_trust_sigmas (0: the term is always trusted).
#include <Eigen/Geometry>
#include <quasiloc/estimation/tracking_window.h>
#include <vector>

namespace quasiloc::map
{
class DistanceField;
}

namespace quasiloc::tracking
{
/** A weight below this leaves the edge term out of the frame. */
constexpr double kEdgeTrustDropWeight = 0.05;

/** The weight w of the edge term for a disagreement [sigmas] and the rule's scale [sigmas]; 1 for a scale <= 0
 *  (off) or a disagreement <= 0. */
double edgeTrustWeight(double disagreement_sigmas, double scale_sigmas);

/** The mean over the points of (min(distance to the map's surfaces at T_world_cam, truncation_m) / sigma)^2; NaN
 *  without points. */
double meanSquaredStereoMapSigmas(const map::DistanceField& field, const Eigen::Isometry3d& T_world_cam,
                                  const std::vector<Eigen::Vector3d>& p_cam, const std::vector<double>& sigma_m,
                                  double truncation_m);

/** The stereo surface term's points and how the window weighs them (MapDistanceTerm). */
struct StereoSurface
{
    std::vector<Eigen::Vector3d> p_cam;
    std::vector<double> sigma_m;
    double truncation_m = 0.15;
    double effective_points = 50;
};

/** The disagreement [sigmas] between the edge optimum and the stereo (above); 0 with fewer than 10 points. */
double edgeStereoDisagreement(const map::DistanceField& field, const Eigen::Isometry3d& T_world_cam_predicted,
                              const Eigen::Isometry3d& T_world_cam_edges, const StereoSurface& stereo);

/** Weighs the frame's edge term (the last of `terms`) by the rule above: its sigma_px divided by sqrt(w), or the
 *  term removed below kEdgeTrustDropWeight. Returns w. */
double weighEdgeTerm(const map::DistanceField& field, const Eigen::Isometry3d& T_world_cam_predicted,
                     const Eigen::Isometry3d& T_world_cam_edges, const StereoSurface& stereo, double scale_sigmas,
                     std::vector<estimation::DirectEdgeTerm>& terms);
}  // namespace quasiloc::tracking
