#pragma once
// A smooth, twice-differentiable body trajectory built from sampled poses (e.g. the EuRoC ground truth of
// cam0), so that an IMU can be synthesised from its derivatives. Position: a uniform cubic B-spline in the
// world frame; orientation: a cumulative uniform cubic B-spline on SO(3) (Kim et al. 1995; derivatives as in
// Sommer et al. 2020). Both are C2: acceleration and angular acceleration are continuous, jerk jumps at the
// knots. Knots lie at tStart() + i * knotSpacing(); an IMU sampled on that grid (e.g. 200 Hz with 0.1 s
// knots) never has a jerk jump inside a sample interval, which keeps numerical integration of it exact to
// high order. The world frame has gravity along -z (EuRoC Vicon frame).
#include <mrpt/poses/CPose3D.h>
#include <quasiloc/core/trajectory_io.h>

#include <Eigen/Core>
#include <memory>

namespace quasiloc::sim
{
struct TrajectorySplineOptions
{
    double knot_spacing_s = 0.1;  ///< spline knot interval (smoothing of Vicon jitter)
};

/** State of the body (IMU) frame at time t, world frame: position, orientation and derivatives. */
struct BodyState
{
    mrpt::poses::CPose3D T_world_body;
    Eigen::Vector3d v_world = Eigen::Vector3d::Zero();           ///< velocity, world frame
    Eigen::Vector3d a_world = Eigen::Vector3d::Zero();           ///< acceleration (no gravity), world frame
    Eigen::Vector3d omega_body = Eigen::Vector3d::Zero();        ///< angular rate, body frame
    Eigen::Vector3d alpha_body = Eigen::Vector3d::Zero();        ///< angular acceleration d(omega_body)/dt
    Eigen::Matrix3d R_world_body = Eigen::Matrix3d::Identity();  ///< rotation of T_world_body, unrounded
    Eigen::Vector3d p_world = Eigen::Vector3d::Zero();           ///< translation of T_world_body
};

/** How well the spline reproduces the poses it was fitted to (body frame, at the distinct samples). */
struct SplineFitStats
{
    size_t num_samples = 0;             ///< distinct poses used
    size_t num_duplicates_dropped = 0;  ///< rows dropped because the next row has the same timestamp
    size_t num_control_points = 0;
    int rotation_iterations = 0;  ///< Gauss-Newton iterations of the SO(3) fit
    double rms_position_m = 0, max_position_m = 0;
    double rms_rotation_rad = 0, max_rotation_rad = 0;
};

class TrajectorySpline
{
   public:
    /** Fits the body trajectory to camera poses T_world_cam0, given the camera's pose in the body frame
     *  (T_body_cam0): T_world_body = T_world_cam0 * inverse(T_body_cam0). Repeated timestamps (EuRoC rows before
     *  ground truth begins) are dropped: a run of rows with one timestamp keeps its last row. Throws InputError
     *  if fewer than 4 distinct poses remain, or on unsorted or non-finite input. */
    static TrajectorySpline fitCameraTrajectory(const core::Trajectory& T_world_cam0,
                                                const mrpt::poses::CPose3D& T_body_cam0,
                                                const TrajectorySplineOptions& options = {});
    /** Same, for poses that already are T_world_body. */
    static TrajectorySpline fitBodyTrajectory(const core::Trajectory& T_world_body,
                                              const TrajectorySplineOptions& options = {});

    double tStart() const;
    double tEnd() const;
    double knotSpacing() const;
    const SplineFitStats& fitStats() const;
    /** Valid for tStart() <= t <= tEnd() (1 us tolerance); std::out_of_range otherwise. */
    BodyState evaluate(double t) const;
    mrpt::poses::CPose3D T_world_body(double t) const { return evaluate(t).T_world_body; }

   private:
    struct Impl;
    std::shared_ptr<const Impl> impl_;
};

}  // namespace quasiloc::sim
