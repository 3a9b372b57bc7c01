#pragma once
// Options of the tracking-window estimator, INI section [Estimator] (EstimatorOptions::declare,
// estimator_options.cpp).
#include <quasiloc/core/declared_options.h>
#include <string>

namespace quasiloc::estimation
{
/** Which structural residuals enter (ablation). */
enum class Primitives
{
    P,
    L,
    PL,
    PLPlane
};

/** The robust loss on whitened residuals. */
enum class RobustLoss
{
    None,
    Huber,
    Cauchy
};

struct EstimatorOptions : public core::DeclaredOptions
{
    Primitives primitives = Primitives::PLPlane;
    bool use_imu = true;
    bool use_temporal_landmarks = true;
    int outer_iterations = 3;
    int inner_iterations = 5;
    RobustLoss robust_loss = RobustLoss::Cauchy;
    double robust_threshold = 2.0;
    double min_depth_m = 0.05;
    double marginal_damping = 1e-9;
    /** IMU gaps (ImuNoise::gap_*): a step between two samples longer than imu_gap_s, and not longer than
     *  imu_gap_max_s, also carries the variance of an unmeasured acceleration / angular rate of these sigmas. */
    double imu_gap_s = 0.025;
    double imu_gap_max_s = 0.5;
    double imu_gap_acc_sigma = 1.0;
    double imu_gap_gyro_sigma = 0.25;

    void declare(core::OptionTable& t) override;
    /** InputError naming `input` and the key for a value out of its declared range (no two keys relate). */
    void check(const std::string& input) const;

    bool usePoints() const { return primitives != Primitives::L; }
    bool useLines() const { return primitives != Primitives::P; }
    bool usePlanes() const { return primitives == Primitives::PLPlane; }
};

}  // namespace quasiloc::estimation
