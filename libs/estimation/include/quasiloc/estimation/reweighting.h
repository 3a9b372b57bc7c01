#pragma once
// Observability- and distribution-aware reweighting (PAPER_NOTES.md, normative):
//
//   H~_0 = D^T H_0 D = U diag(lambda) U^T,   D = diag(I3, L I3),  L = median depth of the map matches
//   a_k = max(0, 1 - sqrt(lambda_k) / tau)                         weakness of eigen-direction u_k
//   H~_ic = D^T H_ic D,   g_ick = u_k^T H~_ic u_k                  what candidate c of factor i adds along u_k
//   mu_ik = sum_c p_ic g_ick,   sigma_ik^2 = sum_c p_ic (g_ick - mu_ik)^2,   g^_ik = max(0, mu_ik - kappa sigma_ik)
//   q_i = sum_k a_k g^_ik / (trace(sum_c p_ic H~_ic) + eps),        W*_i = (1 + beta q_i) W_meas
//
// H_0 and H_ic are 6x6 information matrices of the current pose in the tangent order [dtheta; dp]
// (pose_parametrization.h): rotation first, translation second, so D scales the TRANSLATION block by L.
//
// UNIT CONSISTENCY (why the translation block is the one scaled). Change the unit of length by s (lengths
// x s). Then dp -> s dp and dtheta -> dtheta. A pixel residual (point, point-to-line) is unchanged, so its
// Jacobian becomes [J_theta, J_p / s]; a point-to-plane residual in metres scales by s, and so does its sigma
// (W_meas -> W_meas / s^2), so its whitened Jacobian also becomes [J_theta, J_p / s]. L (a median depth) ->
// s L. Hence J D = [J_theta, L J_p] is unchanged, every H~ = D^T H D is unchanged, and so are lambda_k, u_k,
// a_k, g_ick, mu, sigma and q_i (only eps, a tiny regulariser, is not scaled). Scaling the rotation block
// instead would make H~ depend on s^2 in its translation part. The unit test ScaleInvariance checks this.
//
// Weights are computed once per linearisation and held fixed during one Gauss-Newton solve.
// Modes (ablations): Uniform (W* = W_meas), Observability (kappa = 0 and a single hypothesis: the nominal
// candidate with p = 1), Full (all candidates, kappa as configured).
#include <quasiloc/core/declared_options.h>
#include <quasiloc/estimation/pose_parametrization.h>
#include <string>
#include <vector>

namespace quasiloc::estimation
{
enum class ReweightingMode
{
    Uniform,
    Observability,
    Full
};

/** INI section [Reweighting] (ReweightingOptions::declare, reweighting.cpp). */
struct ReweightingOptions : public core::DeclaredOptions
{
    ReweightingMode mode = ReweightingMode::Full;
    double tau = 1000.0;    ///< a_k = max(0, 1 - sqrt(lambda_k) / tau); same unit as sqrt(lambda)
    double beta = 4.0;      ///< W* = (1 + beta q) W_meas
    double kappa = 1.0;     ///< g^ = max(0, mu - kappa sigma) (full mode only)
    double epsilon = 1e-9;  ///< regulariser of q's denominator

    void declare(core::OptionTable& t) override;
    /** InputError naming `input` and the key for a value out of its declared range (no two keys relate). */
    void check(const std::string& input) const;
};

/** The linearised candidates of one structural factor: H_ic = J_ic^T W_meas J_ic and p_ic. */
struct StructuralCandidates
{
    std::vector<Matrix6d> H;
    std::vector<double> probability;
    int nominal = 0;  ///< index of the candidate the solver uses
};

/** The weak-mode analysis of H_0. */
struct ObservabilityAnalysis
{
    double L = 1.0;
    Vector6d lambda = Vector6d::Zero();  ///< ascending
    Matrix6d U = Matrix6d::Identity();   ///< columns u_k (unit, in the scaled coordinates)
    Vector6d a = Vector6d::Zero();       ///< weakness a_k
};

ObservabilityAnalysis analyzeObservability(const Matrix6d& H0, double L, double tau);

struct ReweightingResult
{
    ObservabilityAnalysis analysis;
    std::vector<double> q;       ///< per factor
    std::vector<double> weight;  ///< W*_i / W_meas = 1 + beta q_i
};

/** Computes q_i and the weights of every structural factor (mode from the options). */
void computeWeights(const ReweightingOptions& options, const Matrix6d& H0, double L,
                    const std::vector<StructuralCandidates>& factors, ReweightingResult& result);

/** mu_ik and sigma_ik of one factor over its candidates (the probabilities as given), and
 *  trace(sum_c p_ic H~_ic). With single_hypothesis only the nominal candidate counts, with p = 1. */
void candidateStatistics(const ObservabilityAnalysis& analysis, const StructuralCandidates& factor,
                         bool single_hypothesis, Vector6d& mu, Vector6d& sigma, double& trace);

/** q_i of one factor given the analysis (kappa as given; probabilities as given). */
double factorScore(const ObservabilityAnalysis& analysis, const StructuralCandidates& factor, double kappa,
                   double epsilon, bool single_hypothesis);

/** Median of the depths (camera z) of the map matches; `fallback` when there is none. */
double medianDepth(std::vector<double> depths, double fallback = 1.0);

}  // namespace quasiloc::estimation
