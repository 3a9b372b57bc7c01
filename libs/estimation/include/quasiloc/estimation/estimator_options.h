#pragma once
// Options of the tracking-window estimator, INI section [Estimator] (every key optional; defaults below).
//
//   [Estimator]
//   primitives = P+L+plane      ; P | L | P+L | P+L+plane: which structural residuals enter (ablation)
//   use_imu = true              ; IMU preintegration and bias random-walk factors (when the input has them)
//   use_temporal_landmarks = true ; stereo reprojection of landmarks seen in the previous and current frame
//   outer_iterations = 3        ; relinearise + reweight + solve rounds (weights fixed within a round)
//   inner_iterations = 5        ; Levenberg-Marquardt iterations per round
//   robust_loss = cauchy        ; none | huber | cauchy (on whitened residuals)
//   robust_threshold = 2.0      ; in sigmas of a single residual; a block of n residuals uses sqrt(n) times it
//   min_depth_m = 0.05          ; map matches closer than this (camera z) do not count for L
//   marginal_damping = 1e-9     ; added to the diagonal of the marginalised block (gauge, unseen landmarks)
#include <mrpt/config/CLoadableOptions.h>

#include <string>

namespace quasiloc::estimation
{
enum class Primitives
{
    P,
    L,
    PL,
    PLPlane
};

struct EstimatorOptions : public mrpt::config::CLoadableOptions
{
    std::string primitives = "P+L+plane";
    bool use_imu = true;
    bool use_temporal_landmarks = true;
    int outer_iterations = 3;
    int inner_iterations = 5;
    std::string robust_loss = "cauchy";
    double robust_threshold = 2.0;
    double min_depth_m = 0.05;
    double marginal_damping = 1e-9;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
    void check(const std::string& input) const;

    Primitives primitiveSet() const;
    bool usePoints() const { return primitiveSet() != Primitives::L; }
    bool useLines() const { return primitiveSet() != Primitives::P; }
    bool usePlanes() const { return primitiveSet() == Primitives::PLPlane; }
};

}  // namespace quasiloc::estimation
