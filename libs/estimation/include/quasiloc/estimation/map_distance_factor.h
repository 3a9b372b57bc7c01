#pragma once
// The camera's stereo points against the LiDAR map's surfaces: a point-to-surface map factor on the current pose.
//
// One residual per stereo point i (left camera frame p_i, from the tracker's sparse stereo matches):
//     d_i = D( T_map_body T_body_cam p_i ) / sigma_i,      r_i = sqrt(2 huber_k(d_i)),
// with D the map's distance field (map::DistanceField: distance to the nearest map point, whose gradient is the
// local surface normal, so this is a point-to-plane residual whose plane is looked up, not associated once), and
// sigma_i = sqrt(sigma_map^2 + sigma_depth(z_i)^2) * sqrt(n / effective_points): the stereo depth noise grows with
// the depth squared, and the n points of one frame share its calibration and the map's errors, so together they
// count as effective_points independent observations (as the direct edge term does). Points farther than
// truncation_m from the map (a person, clutter the survey did not see, a wrong stereo match) keep a constant
// residual with a zero Jacobian; the Huber is inside the residual for the reason given in direct_factor.h.
//
// Why: the direct edge term can be weak or biased in some directions (a view of a corner and a bare floor:
// simulated V1_03's first seconds, where the window followed the edges 15 cm away from the truth while visual-
// inertial odometry alone stayed within 1 cm). The floor and the walls constrain exactly those directions through
// the stereo geometry, with no appearance involved.
#include <ceres/cost_function.h>

#include <Eigen/Geometry>
#include <quasiloc/map/distance_field.h>
#include <vector>

namespace quasiloc::estimation
{
class MapDistanceCostFunction final : public ceres::CostFunction
{
   public:
    /** field must outlive the cost function; one sigma (metres, > 0) per point. InputError for sizes that differ,
     *  no point, or a sigma <= 0. */
    MapDistanceCostFunction(const map::DistanceField& field, std::vector<Eigen::Vector3d> p_cam,
                            std::vector<double> sigma_m, const Eigen::Isometry3d& T_body_cam, double truncation_m,
                            double huber_sigmas);
    bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

   private:
    /** Residuals (and Jacobian rows when J is set) of points [begin, end). */
    void evaluatePoints(size_t begin, size_t end, const Eigen::Isometry3d& T_map_body, double* residuals,
                        double* J) const;
    const map::DistanceField& field_;
    std::vector<Eigen::Vector3d> p_body_;
    std::vector<double> inv_sigma_;
    double truncation_m_, huber_;
};

}  // namespace quasiloc::estimation
