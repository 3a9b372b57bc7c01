#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/estimation/imu_preintegration.h>

namespace quasiloc::estimation
{
ImuPreintegration::ImuPreintegration(const ImuNoise& noise, const Eigen::Vector3d& gyro_bias,
                                     const Eigen::Vector3d& acc_bias)
    : noise_(noise), bg0_(gyro_bias), ba0_(acc_bias)
{
    reset();
}

void ImuPreintegration::reset()
{
    dt_ = 0;
    dR_.setIdentity();
    dv_.setZero();
    dp_.setZero();
    JR_g_.setZero();
    Jv_g_.setZero();
    Jv_a_.setZero();
    Jp_g_.setZero();
    Jp_a_.setZero();
    cov_.setZero();
}

void ImuPreintegration::integrate(const Eigen::Vector3d& acc, const Eigen::Vector3d& gyro, double dt)
{
    core::require(std::isfinite(dt) && dt > 0, "IMU sample", "integration step must be > 0");
    samples_.push_back({acc, gyro, dt});
    const Eigen::Vector3d a = acc - ba0_, w = gyro - bg0_;
    const double dt2 = dt * dt;
    const Eigen::Matrix3d a_hat = hat(a);
    const Eigen::Matrix3d dR_inc = expSO3(w * dt);
    const Eigen::Matrix3d Jr = rightJacobianSO3(w * dt);

    // Covariance of [dphi; dv; dp] (Forster eq. 62-63), with the deltas of the previous step.
    Matrix9d A = Matrix9d::Identity();
    A.block<3, 3>(0, 0) = dR_inc.transpose();
    A.block<3, 3>(3, 0) = -dR_ * a_hat * dt;
    A.block<3, 3>(6, 0) = -0.5 * dR_ * a_hat * dt2;
    A.block<3, 3>(6, 3) = Eigen::Matrix3d::Identity() * dt;
    Eigen::Matrix<double, 9, 3> Bg = Eigen::Matrix<double, 9, 3>::Zero(), Ba = Eigen::Matrix<double, 9, 3>::Zero();
    Bg.topRows<3>() = Jr * dt;
    Ba.middleRows<3>(3) = dR_ * dt;
    Ba.bottomRows<3>() = 0.5 * dR_ * dt2;
    const bool gap = dt > noise_.gap_s && dt <= noise_.gap_max_s;
    const double var_g = noise_.gyro_noise_density * noise_.gyro_noise_density / dt +
                         (gap ? noise_.gap_gyro_sigma * noise_.gap_gyro_sigma : 0.0);
    const double var_a = noise_.acc_noise_density * noise_.acc_noise_density / dt +
                         (gap ? noise_.gap_acc_sigma * noise_.gap_acc_sigma : 0.0);
    cov_ = A * cov_ * A.transpose() + var_g * Bg * Bg.transpose() + var_a * Ba * Ba.transpose();

    // Bias Jacobians (Forster appendix B), position and velocity before rotation.
    Jp_a_ += Jv_a_ * dt - 0.5 * dR_ * dt2;
    Jp_g_ += Jv_g_ * dt - 0.5 * dR_ * a_hat * JR_g_ * dt2;
    Jv_a_ -= dR_ * dt;
    Jv_g_ -= dR_ * a_hat * JR_g_ * dt;
    JR_g_ = dR_inc.transpose() * JR_g_ - Jr * dt;

    dp_ += dv_ * dt + 0.5 * dR_ * a * dt2;
    dv_ += dR_ * a * dt;
    dR_ = dR_ * dR_inc;
    // Keep dR orthonormal over long intervals.
    const Eigen::Quaterniond q(dR_);
    dR_ = q.normalized().toRotationMatrix();
    dt_ += dt;
}

void ImuPreintegration::integrateInterval(const std::vector<ImuMeasurement>& samples, double t_i, double t_j)
{
    core::require(t_j > t_i, "IMU interval", "t_j must be after t_i");
    int used = 0;
    for (size_t k = 0; k < samples.size(); ++k)
    {
        const double t0 = (k == 0) ? std::min(samples[k].t, t_i) : samples[k].t;
        const double t1 = (k + 1 < samples.size()) ? samples[k + 1].t : t_j;
        const double a = std::max(t0, t_i), b = std::min(t1, t_j);
        if (b - a <= 1e-12) continue;
        integrate(samples[k].acc, samples[k].gyro, b - a);
        ++used;
    }
    core::require(used > 0, "IMU interval", "no IMU sample covers [t_i, t_j]");
}

void ImuPreintegration::repropagate(const Eigen::Vector3d& gyro_bias, const Eigen::Vector3d& acc_bias)
{
    const std::vector<Sample> samples = std::move(samples_);
    samples_.clear();
    bg0_ = gyro_bias;
    ba0_ = acc_bias;
    reset();
    for (const auto& s : samples) integrate(s.acc, s.gyro, s.dt);
}

Eigen::Matrix3d ImuPreintegration::correctedDeltaR(const Eigen::Vector3d& bg) const
{
    return dR_ * expSO3(JR_g_ * (bg - bg0_));
}
Eigen::Vector3d ImuPreintegration::correctedDeltaV(const Eigen::Vector3d& bg, const Eigen::Vector3d& ba) const
{
    return dv_ + Jv_g_ * (bg - bg0_) + Jv_a_ * (ba - ba0_);
}
Eigen::Vector3d ImuPreintegration::correctedDeltaP(const Eigen::Vector3d& bg, const Eigen::Vector3d& ba) const
{
    return dp_ + Jp_g_ * (bg - bg0_) + Jp_a_ * (ba - ba0_);
}

void ImuPreintegration::predict(const Eigen::Isometry3d& T_i, const Eigen::Vector3d& v_i, const Eigen::Vector3d& bg,
                                const Eigen::Vector3d& ba, Eigen::Isometry3d& T_j, Eigen::Vector3d& v_j) const
{
    const Eigen::Vector3d g = noise_.gravity();
    const Eigen::Matrix3d& R_i = T_i.linear();
    T_j = Eigen::Isometry3d::Identity();
    T_j.linear() = R_i * correctedDeltaR(bg);
    T_j.translation() = T_i.translation() + v_i * dt_ + 0.5 * g * dt_ * dt_ + R_i * correctedDeltaP(bg, ba);
    v_j = v_i + g * dt_ + R_i * correctedDeltaV(bg, ba);
}

// ------------------------------------------------------------------------------------------ ImuFactor
ImuFactor::ImuFactor(const ImuPreintegration& preintegration) : pre_(&preintegration)
{
    // Regularise: a very short interval has a nearly singular covariance.
    const Matrix9d cov = pre_->covariance() + 1e-12 * Matrix9d::Identity();
    const Matrix9d info = cov.inverse();
    sqrt_info_ = Eigen::LLT<Matrix9d>(0.5 * (info + info.transpose())).matrixU();
}

void ImuFactor::linearize(const Eigen::Isometry3d& T_i, const Vector9d& sb_i, const Eigen::Isometry3d& T_j,
                          const Vector9d& sb_j, Vector9d& r, Jac96* J_Ti, Jac99* J_sbi, Jac96* J_Tj, Jac99* J_sbj) const
{
    const double dt = pre_->dt();
    const Eigen::Vector3d g = pre_->noise().gravity();
    const Eigen::Matrix3d& R_i = T_i.linear();
    const Eigen::Matrix3d& R_j = T_j.linear();
    const Eigen::Vector3d p_i = T_i.translation(), p_j = T_j.translation();
    const Eigen::Vector3d v_i = sb_i.head<3>(), v_j = sb_j.head<3>();
    const Eigen::Vector3d bg = sb_i.segment<3>(3), ba = sb_i.tail<3>();
    const Eigen::Vector3d dbg = bg - pre_->gyroBias();

    const Eigen::Matrix3d dR = pre_->correctedDeltaR(bg);
    const Eigen::Vector3d v_term = R_i.transpose() * (v_j - v_i - g * dt);
    const Eigen::Vector3d p_term = R_i.transpose() * (p_j - p_i - v_i * dt - 0.5 * g * dt * dt);
    Vector9d e;
    e.head<3>() = logSO3(dR.transpose() * R_i.transpose() * R_j);
    e.segment<3>(3) = v_term - pre_->correctedDeltaV(bg, ba);
    e.tail<3>() = p_term - pre_->correctedDeltaP(bg, ba);
    r = sqrt_info_ * e;

    const Eigen::Vector3d r_R = e.head<3>();
    const Eigen::Matrix3d JrInv = rightJacobianInvSO3(r_R);
    if (J_Ti)
    {
        Jac96 J = Jac96::Zero();
        J.block<3, 3>(0, 0) = -JrInv * R_j.transpose() * R_i;
        J.block<3, 3>(3, 0) = hat(v_term);
        J.block<3, 3>(6, 0) = hat(p_term);
        J.block<3, 3>(6, 3) = -Eigen::Matrix3d::Identity();
        *J_Ti = sqrt_info_ * J;
    }
    if (J_sbi)
    {
        Jac99 J = Jac99::Zero();
        J.block<3, 3>(0, 3) =
            -JrInv * expSO3(r_R).transpose() * rightJacobianSO3(pre_->dR_dbg() * dbg) * pre_->dR_dbg();
        J.block<3, 3>(3, 0) = -R_i.transpose();
        J.block<3, 3>(3, 3) = -pre_->dv_dbg();
        J.block<3, 3>(3, 6) = -pre_->dv_dba();
        J.block<3, 3>(6, 0) = -R_i.transpose() * dt;
        J.block<3, 3>(6, 3) = -pre_->dp_dbg();
        J.block<3, 3>(6, 6) = -pre_->dp_dba();
        *J_sbi = sqrt_info_ * J;
    }
    if (J_Tj)
    {
        Jac96 J = Jac96::Zero();
        J.block<3, 3>(0, 0) = JrInv;
        J.block<3, 3>(6, 3) = R_i.transpose() * R_j;
        *J_Tj = sqrt_info_ * J;
    }
    if (J_sbj)
    {
        Jac99 J = Jac99::Zero();
        J.block<3, 3>(3, 0) = R_i.transpose();
        *J_sbj = sqrt_info_ * J;
    }
}

bool ImuFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const
{
    Vector9d r;
    Jac96 J_Ti, J_Tj;
    Jac99 J_sbi, J_sbj;
    auto want = [&](int k) { return jacobians && jacobians[k]; };
    linearize(paramsToPose(parameters[0]), Eigen::Map<const Vector9d>(parameters[1]), paramsToPose(parameters[2]),
              Eigen::Map<const Vector9d>(parameters[3]), r, want(0) ? &J_Ti : nullptr, want(1) ? &J_sbi : nullptr,
              want(2) ? &J_Tj : nullptr, want(3) ? &J_sbj : nullptr);
    Eigen::Map<Vector9d>{residuals} = r;
    using RM96 = Eigen::Matrix<double, 9, 6, Eigen::RowMajor>;
    if (want(0)) liftPoseJacobian(RM96(J_Ti).data(), 9, jacobians[0]);
    if (want(1)) Eigen::Map<Eigen::Matrix<double, 9, 9, Eigen::RowMajor>>{jacobians[1]} = J_sbi;
    if (want(2)) liftPoseJacobian(RM96(J_Tj).data(), 9, jacobians[2]);
    if (want(3)) Eigen::Map<Eigen::Matrix<double, 9, 9, Eigen::RowMajor>>{jacobians[3]} = J_sbj;
    return true;
}

// ------------------------------------------------------------------------------- BiasRandomWalkFactor
BiasRandomWalkFactor::BiasRandomWalkFactor(const ImuNoise& noise, double dt)
{
    core::require(dt > 0, "BiasRandomWalkFactor", "dt must be > 0");
    const double sg = noise.gyro_random_walk * std::sqrt(dt), sa = noise.acc_random_walk * std::sqrt(dt);
    sqrt_info_ << Eigen::Vector3d::Constant(1.0 / sg), Eigen::Vector3d::Constant(1.0 / sa);
}

bool BiasRandomWalkFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const
{
    const Eigen::Map<const Vector9d> sb_i(parameters[0]), sb_j(parameters[1]);
    Eigen::Map<Eigen::Matrix<double, 6, 1>>{residuals} = sqrt_info_.cwiseProduct(sb_j.tail<6>() - sb_i.tail<6>());
    for (int k = 0; k < 2; ++k)
    {
        if (!jacobians || !jacobians[k]) continue;
        Eigen::Map<Eigen::Matrix<double, 6, 9, Eigen::RowMajor>> J(jacobians[k]);
        J.setZero();
        J.rightCols<6>().diagonal() = (k == 0 ? -1.0 : 1.0) * sqrt_info_;
    }
    return true;
}

}  // namespace quasiloc::estimation
