#pragma once
// On-manifold IMU preintegration (Forster, Carlone, Dellaert, Scaramuzza, "On-Manifold Preintegration for
// Real-Time Visual-Inertial Odometry", T-RO 2017) and the factors that use it.
//
// Model: specific force f = R_map_body^T (a_map - g) + b_a + noise, rate w = omega_body + b_g + noise, with
// g = (0, 0, -gravity). Between frames i and j the preintegrated deltas (dR, dv, dp) are computed at the
// linearisation biases (bg0, ba0); a bias change db is applied to first order with the bias Jacobians
// (eq. 44). The 9x9 covariance of [dphi; dv; dp] is propagated sample by sample (eq. 62-63) from the
// continuous-time noise densities (sigma_discrete^2 = density^2 / dt).
//
// ImuFactor (9 residuals, [r_R; r_v; r_p]) connects (pose_i, speed_bias_i, pose_j, speed_bias_j), where a
// speed_bias block is [v_map; b_g; b_a] (9). BiasRandomWalkFactor (6) ties b_j to b_i with covariance
// random_walk^2 * dt. Pose blocks follow pose_parametrization.h (right perturbation [dtheta; dp]).
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <quasiloc/estimation/measurements.h>
#include <quasiloc/estimation/pose_parametrization.h>
#include <vector>

namespace quasiloc::estimation
{
using Matrix9d = Eigen::Matrix<double, 9, 9>;
using Vector9d = Eigen::Matrix<double, 9, 1>;

struct ImuNoise
{
    double gyro_noise_density = 1.6968e-4;  ///< rad/s/sqrt(Hz)
    double acc_noise_density = 2.0e-3;      ///< m/s^2/sqrt(Hz)
    double gyro_random_walk = 1.9393e-5;    ///< rad/s^2/sqrt(Hz)
    double acc_random_walk = 3.0e-3;        ///< m/s^3/sqrt(Hz)
    double gravity_m_s2 = 9.81;
    /** A step longer than this between two IMU samples is a gap (dropped samples): the motion in it was not
     *  measured, so the step also carries the variance of an unmeasured acceleration and angular rate of the
     *  sigmas below (the sensor noise alone would claim the held sample is exact over the whole gap). */
    double gap_s = 0.025;
    /** Only gaps up to this long get that variance. A longer one leaves the prediction as uncertain as the
     *  sensor claims, so the tracker's gate rejects the large map corrections it needs and the loss check and the
     *  relocalization take over: with the variance of a 1 s gap (0.5 m), the gate let through a wrong alignment
     *  whose velocity and biases the window then kept (docs/reliability.md). */
    double gap_max_s = 0.5;
    double gap_acc_sigma = 1.0;    ///< m/s^2 (0: off)
    double gap_gyro_sigma = 0.25;  ///< rad/s (0: off)
    Eigen::Vector3d gravity() const { return Eigen::Vector3d(0, 0, -gravity_m_s2); }
};

class ImuPreintegration
{
   public:
    ImuPreintegration(const ImuNoise& noise, const Eigen::Vector3d& gyro_bias, const Eigen::Vector3d& acc_bias);

    /** Integrates one sample held constant over dt seconds (dt > 0). */
    void integrate(const Eigen::Vector3d& acc, const Eigen::Vector3d& gyro, double dt);
    /** Integrates the samples between t_i and t_j: sample k holds from max(t_k, t_i) to min(t_{k+1}, t_j);
     *  the first sample also covers [t_i, t_0) if it starts late. InputError if there is none. */
    void integrateInterval(const std::vector<ImuMeasurement>& samples, double t_i, double t_j);
    /** Restarts from the stored samples with new linearisation biases (after a large bias change). */
    void repropagate(const Eigen::Vector3d& gyro_bias, const Eigen::Vector3d& acc_bias);

    double dt() const { return dt_; }
    const Eigen::Matrix3d& deltaR() const { return dR_; }
    const Eigen::Vector3d& deltaV() const { return dv_; }
    const Eigen::Vector3d& deltaP() const { return dp_; }
    const Matrix9d& covariance() const { return cov_; }
    const Eigen::Vector3d& gyroBias() const { return bg0_; }
    const Eigen::Vector3d& accBias() const { return ba0_; }
    const ImuNoise& noise() const { return noise_; }
    const Eigen::Matrix3d& dR_dbg() const { return JR_g_; }
    const Eigen::Matrix3d& dv_dbg() const { return Jv_g_; }
    const Eigen::Matrix3d& dv_dba() const { return Jv_a_; }
    const Eigen::Matrix3d& dp_dbg() const { return Jp_g_; }
    const Eigen::Matrix3d& dp_dba() const { return Jp_a_; }

    /** Deltas corrected to first order for biases (bg, ba) (Forster eq. 44). */
    Eigen::Matrix3d correctedDeltaR(const Eigen::Vector3d& bg) const;
    Eigen::Vector3d correctedDeltaV(const Eigen::Vector3d& bg, const Eigen::Vector3d& ba) const;
    Eigen::Vector3d correctedDeltaP(const Eigen::Vector3d& bg, const Eigen::Vector3d& ba) const;

    /** State j predicted from state i (pose T_map_body, velocity) with biases (bg, ba). */
    void predict(const Eigen::Isometry3d& T_i, const Eigen::Vector3d& v_i, const Eigen::Vector3d& bg,
                 const Eigen::Vector3d& ba, Eigen::Isometry3d& T_j, Eigen::Vector3d& v_j) const;

   private:
    void reset();
    ImuNoise noise_;
    Eigen::Vector3d bg0_, ba0_;
    double dt_ = 0;
    Eigen::Matrix3d dR_;
    Eigen::Vector3d dv_, dp_;
    Eigen::Matrix3d JR_g_, Jv_g_, Jv_a_, Jp_g_, Jp_a_;
    Matrix9d cov_;
    struct Sample
    {
        Eigen::Vector3d acc, gyro;
        double dt;
    };
    std::vector<Sample> samples_;
};

class ImuFactor final : public ceres::SizedCostFunction<9, kPoseSize, kSpeedBiasSize, kPoseSize, kSpeedBiasSize>
{
   public:
    /** Keeps a pointer: `preintegration` must outlive the factor. */
    explicit ImuFactor(const ImuPreintegration& preintegration);
    bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

    using Jac96 = Eigen::Matrix<double, 9, 6>;
    using Jac99 = Eigen::Matrix<double, 9, 9>;
    /** Whitened residual and Jacobians w.r.t. the tangent spaces of the four blocks (any may be null). */
    void linearize(const Eigen::Isometry3d& T_i, const Vector9d& sb_i, const Eigen::Isometry3d& T_j,
                   const Vector9d& sb_j, Vector9d& r, Jac96* J_Ti, Jac99* J_sbi, Jac96* J_Tj, Jac99* J_sbj) const;

   private:
    const ImuPreintegration* pre_;
    Matrix9d sqrt_info_;  ///< upper-triangular L^T with L L^T = covariance^-1
};

class BiasRandomWalkFactor final : public ceres::SizedCostFunction<6, kSpeedBiasSize, kSpeedBiasSize>
{
   public:
    BiasRandomWalkFactor(const ImuNoise& noise, double dt);
    bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

   private:
    Eigen::Matrix<double, 6, 1> sqrt_info_;  ///< diagonal
};

}  // namespace quasiloc::estimation
