#include <quasiloc/core/error.h>
#include <quasiloc/estimation/estimator_options.h>

#include <quasiloc/core/ini_read.h>

namespace quasiloc::estimation
{
void EstimatorOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    primitives = cfg.read_string(s, "primitives", primitives);
    use_imu = core::readIniBool(cfg, s, "use_imu", use_imu);
    use_temporal_landmarks = core::readIniBool(cfg, s, "use_temporal_landmarks", use_temporal_landmarks);
    outer_iterations = core::readIniInt(cfg, s, "outer_iterations", outer_iterations);
    inner_iterations = core::readIniInt(cfg, s, "inner_iterations", inner_iterations);
    robust_loss = cfg.read_string(s, "robust_loss", robust_loss);
    robust_threshold = core::readIniDouble(cfg, s, "robust_threshold", robust_threshold);
    min_depth_m = core::readIniDouble(cfg, s, "min_depth_m", min_depth_m);
    marginal_damping = core::readIniDouble(cfg, s, "marginal_damping", marginal_damping);
}

void EstimatorOptions::saveToConfigFile(mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
    cfg.write(s, "primitives", primitives, 24, 10, "P | L | P+L | P+L+plane");
    cfg.write(s, "use_imu", use_imu ? "true" : "false", 24, 10);
    cfg.write(s, "use_temporal_landmarks", use_temporal_landmarks ? "true" : "false", 24, 10);
    cfg.write(s, "outer_iterations", outer_iterations, 24, 10, "relinearise + reweight + solve rounds");
    cfg.write(s, "inner_iterations", inner_iterations, 24, 10, "LM iterations per round");
    cfg.write(s, "robust_loss", robust_loss, 24, 10, "none | huber | cauchy");
    cfg.write(s, "robust_threshold", robust_threshold, 24, 10, "sigmas of one residual");
    cfg.write(s, "min_depth_m", min_depth_m, 24, 10);
    cfg.write(s, "marginal_damping", marginal_damping, 24, 10);
}

Primitives EstimatorOptions::primitiveSet() const
{
    if (primitives == "P") return Primitives::P;
    if (primitives == "L") return Primitives::L;
    if (primitives == "P+L") return Primitives::PL;
    if (primitives == "P+L+plane") return Primitives::PLPlane;
    throw core::InputError("[Estimator] primitives", "'" + primitives + "' is not one of P, L, P+L, P+L+plane");
}

void EstimatorOptions::check(const std::string& input) const
{
    const std::string k = input + ": [Estimator] ";
    primitiveSet();
    core::require(robust_loss == "none" || robust_loss == "huber" || robust_loss == "cauchy", k + "robust_loss",
                  "'" + robust_loss + "' is not one of none, huber, cauchy");
    core::require(outer_iterations >= 1 && outer_iterations <= 100, k + "outer_iterations", "must be in [1, 100]");
    core::require(inner_iterations >= 1 && inner_iterations <= 1000, k + "inner_iterations", "must be in [1, 1000]");
    core::require(robust_threshold > 0, k + "robust_threshold", "must be > 0");
    core::require(min_depth_m >= 0, k + "min_depth_m", "must be >= 0");
    core::require(marginal_damping >= 0, k + "marginal_damping", "must be >= 0");
}

}  // namespace quasiloc::estimation
