#pragma once
// The direct map alignment's result as a pose measurement for the estimator window, with an information that
// follows what the map edges actually observe (issue 9; the paper's observability-aware reweighting applied to
// the map term). A fixed isotropic information (sigma_m, sigma_rad in every direction) claims the alignment pins
// down directions the edges cannot see (a wall seen head-on says little about sliding along it): there the
// measurement merely repeats the prediction the alignment started from, and locks the IMU drift in.
//
// observability: the alignment's Gauss-Newton Hessian H (DirectAlignmentStats::hessian, camera tangent
// [dtheta; dp]) is made unitless with D = diag(sigma_rad I3, sigma_m I3): Hn = D H D = V diag(l) V^T. The
// measurement's information is D^-1 V diag(min(1, l / l_med)) V^T D^-1 with l_med the median eigenvalue: the
// directions observed at least as well as the median one keep the configured sigma, a direction observed k times
// less gets k times less information, an unobserved one none. Then it is moved from the camera tangent to the
// body tangent (the state's) through the extrinsic.
#include <Eigen/Geometry>
#include <quasiloc/estimation/pose_parametrization.h>

namespace quasiloc::estimation
{
/** Information (camera tangent) with the configured sigmas in every direction. */
Matrix6d fixedMapInformation(double sigma_rad, double sigma_m);

/** Information (camera tangent) shaped by the alignment's Hessian as in the file comment; the fixed one when H
 *  is zero or not finite. */
Matrix6d observabilityMapInformation(const Matrix6d& hessian_cam, double sigma_rad, double sigma_m);

/** A camera-tangent information as a body-tangent one, for the pose T_map_body with T_map_cam = T_map_body *
 *  T_body_cam: I_body = A^T I_cam A, A = d(delta_cam)/d(delta_body). */
Matrix6d cameraToBodyInformation(const Matrix6d& information_cam, const Eigen::Isometry3d& T_body_cam);

}  // namespace quasiloc::estimation
