#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/estimation/reweighting.h>

namespace quasiloc::estimation
{
void ReweightingOptions::declare(core::OptionTable& t)
{
    using core::Range;
    t.addEnum("mode", mode,
              {{"uniform", ReweightingMode::Uniform},
               {"observability", ReweightingMode::Observability},
               {"full", ReweightingMode::Full}},
              "uniform: W* = W_meas; observability: kappa = 0, the nominal candidate only; full: all candidates");
    t.add("tau", tau, "", Range::above(0), "a_k = max(0, 1 - sqrt(lambda_k) / tau); same unit as sqrt(lambda)");
    t.add("beta", beta, "", Range::atLeast(0), "W* = (1 + beta q) W_meas");
    t.add("kappa", kappa, "", Range::atLeast(0), "g^ = max(0, mu - kappa sigma) (full mode only)");
    t.add("epsilon", epsilon, "", Range::above(0), "regulariser of q's denominator");
}

void ReweightingOptions::check(const std::string& input) const { checkRanges(input, "Reweighting"); }

ObservabilityAnalysis analyzeObservability(const Matrix6d& H0, double L, double tau)
{
    core::require(std::isfinite(L) && L > 0, "reweighting", "L (median map-match depth) must be > 0");
    ObservabilityAnalysis out;
    out.L = L;
    Matrix6d Ht = H0;
    // D^T H D with D = diag(I3, L I3): the translation rows and columns scale by L.
    Ht.bottomRows<3>() *= L;
    Ht.rightCols<3>() *= L;
    Eigen::SelfAdjointEigenSolver<Matrix6d> eig(0.5 * (Ht + Ht.transpose()));
    out.lambda = eig.eigenvalues().cwiseMax(0.0);
    out.U = eig.eigenvectors();
    for (int k = 0; k < 6; ++k) out.a[k] = std::max(0.0, 1.0 - std::sqrt(out.lambda[k]) / tau);
    return out;
}

void candidateStatistics(const ObservabilityAnalysis& an, const StructuralCandidates& f, bool single_hypothesis,
                         Vector6d& mu, Vector6d& sigma, double& trace)
{
    mu.setZero();
    sigma.setZero();
    trace = 0.0;
    if (f.H.empty()) return;
    // v_k = D u_k, so g_ick = u_k^T D^T H_ic D u_k = v_k^T H_ic v_k without forming H~_ic.
    Matrix6d V = an.U;
    V.bottomRows<3>() *= an.L;
    const double L2 = an.L * an.L;
    const size_t first = single_hypothesis ? static_cast<size_t>(f.nominal) : 0;
    const size_t last = single_hypothesis ? first + 1 : f.H.size();
    // One pass with the weighted sums of g and g^2 (p sums to 1): var = E[g^2] - mu^2, clamped at 0.
    Vector6d g2 = Vector6d::Zero();
    for (size_t c = first; c < last; ++c)
    {
        const double p = single_hypothesis ? 1.0 : f.probability[c];
        const Matrix6d& H = f.H[c];
        trace += p * (H.topLeftCorner<3, 3>().trace() + L2 * H.bottomRightCorner<3, 3>().trace());
        const Matrix6d HV = H.selfadjointView<Eigen::Upper>() * V;
        const Vector6d g = (V.cwiseProduct(HV)).colwise().sum().transpose();
        mu += p * g;
        g2 += p * g.cwiseProduct(g);
    }
    // Relative cancellation guard: identical candidates must give sigma = 0 exactly, not sqrt(rounding).
    for (int k = 0; k < 6; ++k)
    {
        const double var = g2[k] - mu[k] * mu[k];
        sigma[k] = (var > 1e-12 * mu[k] * mu[k]) ? std::sqrt(var) : 0.0;
    }
}

double factorScore(const ObservabilityAnalysis& an, const StructuralCandidates& f, double kappa, double epsilon,
                   bool single_hypothesis)
{
    Vector6d mu, sigma;
    double trace = 0.0;
    candidateStatistics(an, f, single_hypothesis, mu, sigma, trace);
    double num = 0.0;
    for (int k = 0; k < 6; ++k)
        if (an.a[k] > 0) num += an.a[k] * std::max(0.0, mu[k] - kappa * sigma[k]);
    return num / (trace + epsilon);
}

void computeWeights(const ReweightingOptions& options, const Matrix6d& H0, double L,
                    const std::vector<StructuralCandidates>& factors, ReweightingResult& result)
{
    const ReweightingMode mode = options.mode;
    result.q.assign(factors.size(), 0.0);
    result.weight.assign(factors.size(), 1.0);
    if (mode == ReweightingMode::Uniform) return;
    result.analysis = analyzeObservability(H0, L, options.tau);
    const bool single = (mode == ReweightingMode::Observability);
    const double kappa = single ? 0.0 : options.kappa;
    for (size_t i = 0; i < factors.size(); ++i)
    {
        result.q[i] = factorScore(result.analysis, factors[i], kappa, options.epsilon, single);
        result.weight[i] = 1.0 + options.beta * result.q[i];
    }
}

double medianDepth(std::vector<double> depths, double fallback)
{
    depths.erase(std::remove_if(depths.begin(), depths.end(), [](double d) { return !(d > 0) || !std::isfinite(d); }),
                 depths.end());
    if (depths.empty()) return fallback;
    const size_t mid = depths.size() / 2;
    std::nth_element(depths.begin(), depths.begin() + mid, depths.end());
    return depths[mid];
}

}  // namespace quasiloc::estimation
