// bench_estimation: pose accuracy of the tracking-window estimator on random image-free scenes, and the
// reweighting time.
//   bench_estimation [--trials N] [--seed S] [--set Section.key=value]... [google-benchmark flags]
// 1. For each layout (room, corridor, single wall) and >= 200 trials: translation / rotation error of the
//    camera pose for the weighting ablation (uniform / observability only / full, primitives P+L+plane)
//    and the primitive ablation (P / L / P+L / P+L+plane, full weighting). The same scenes are used for
//    every configuration. Errors are in the map frame, unaligned.
// 2. Reweighting time per frame for 200 structural factors with 3 candidates each (bound 0.1 ms), measured
//    with a steady clock (median of 2000 runs) and by Google Benchmark.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <map>
#include <mrpt/config/CConfigFileMemory.h>
#include <quasiloc/core/error.h>
#include <quasiloc/estimation/synthetic_scene.h>
#include <quasiloc/estimation/tracking_window.h>
#include <string>
#include <vector>

using namespace quasiloc;
using namespace quasiloc::estimation;

namespace
{
constexpr double kReweightBoundMs = 0.1;

struct Config
{
    std::string name;
    ReweightingMode mode;
    Primitives primitives;
};
const std::vector<Config> kConfigs = {{"uniform     P+L+plane", ReweightingMode::Uniform, Primitives::PLPlane},
                                      {"observabil. P+L+plane", ReweightingMode::Observability, Primitives::PLPlane},
                                      {"full        P+L+plane", ReweightingMode::Full, Primitives::PLPlane},
                                      {"full        P", ReweightingMode::Full, Primitives::P},
                                      {"full        L", ReweightingMode::Full, Primitives::L},
                                      {"full        P+L", ReweightingMode::Full, Primitives::PL}};

/** The INI name of the present value of `key` (e.g. an enum's). */
std::string valueText(const core::DeclaredOptions& options, const std::string& key)
{
    for (const auto& d : options.describe())
        if (d.key == key) return d.default_value;
    return "?";
}

struct Errors
{
    std::vector<double> t_cm, r_deg;
    int failures = 0;
};

double median(std::vector<double> v)
{
    if (v.empty()) return 0;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
}
double mean(const std::vector<double>& v)
{
    double s = 0;
    for (double x : v) s += x;
    return v.empty() ? 0 : s / v.size();
}
double rmse(const std::vector<double>& v)
{
    double s = 0;
    for (double x : v) s += x * x;
    return v.empty() ? 0 : std::sqrt(s / v.size());
}

void addError(Errors& e, const Eigen::Isometry3d& T_est, const Eigen::Isometry3d& T_true)
{
    e.t_cm.push_back(100.0 * (T_est.translation() - T_true.translation()).norm());
    e.r_deg.push_back(180.0 / M_PI * logSO3(T_true.linear().transpose() * T_est.linear()).norm());
}

void runAccuracy(int trials, unsigned seed, const EstimatorOptions& est_base, const ReweightingOptions& rw_base,
                 bool misspecified)
{
    std::printf("\n## Pose error over %d random frames per layout (camera position error [cm], rotation [deg])\n",
                trials);
    std::printf("## noise model: %s\n", misspecified
                                            ? "MISSPECIFIED (prior sigma 3x too small, map-point noise 3x its sigma)"
                                            : "as stated (every sigma is the true one)");
    std::printf("%-11s %-22s %8s %8s %8s %8s %8s %6s\n", "layout", "configuration", "mean_cm", "med_cm", "rmse_cm",
                "mean_deg", "med_deg", "fail");
    for (SceneLayout layout : {SceneLayout::Room, SceneLayout::Corridor, SceneLayout::SingleWall})
    {
        SceneOptions so;
        so.layout = layout;
        if (misspecified)
        {
            so.prior_overconfidence = 3.0;
            so.point_noise_factor = 3.0;
        }
        std::map<std::string, Errors> errors;
        Errors initial;
        double wrong_share = 0;
        Vector6d sqrt_lambda_sum = Vector6d::Zero();
        std::mt19937 rng(seed);
        for (int t = 0; t < trials; ++t)
        {
            const SyntheticFrame f = makeSyntheticFrame(so, rng);
            addError(initial, f.guess.T_map_body, f.T_map_body_true);
            wrong_share += double(f.wrong_nominal_lines + f.wrong_nominal_planes) /
                           std::max<size_t>(1, f.lines.size() + f.planes.size());
            WindowInput in;
            in.stereo = &f.stereo;
            in.prior = f.prior;
            in.current = f.guess;
            in.points = f.points;
            in.lines = f.lines;
            in.planes = f.planes;
            for (const Config& c : kConfigs)
            {
                EstimatorOptions eo = est_base;
                eo.primitives = c.primitives;
                ReweightingOptions ro = rw_base;
                ro.mode = c.mode;
                WindowResult res;
                Errors& e = errors[c.name];
                if (!estimateWindow(eo, ro, in, res)) ++e.failures;
                if (c.mode == ReweightingMode::Full && c.primitives == Primitives::PLPlane)
                    sqrt_lambda_sum += res.reweighting.analysis.lambda.cwiseSqrt();
                addError(e, res.current.T_map_body, f.T_map_body_true);
            }
        }
        const std::string ln = toString(layout);
        std::printf("%-11s %-22s %8.2f %8.2f %8.2f %8.3f %8.3f %6s\n", ln.c_str(), "(initial guess)",
                    mean(initial.t_cm), median(initial.t_cm), rmse(initial.t_cm), mean(initial.r_deg),
                    median(initial.r_deg), "-");
        for (const Config& c : kConfigs)
        {
            const Errors& e = errors[c.name];
            std::printf("%-11s %-22s %8.2f %8.2f %8.2f %8.3f %8.3f %6d\n", ln.c_str(), c.name.c_str(), mean(e.t_cm),
                        median(e.t_cm), rmse(e.t_cm), mean(e.r_deg), median(e.r_deg), e.failures);
        }
        std::printf("%-11s share of structural factors with a wrong nominal candidate: %.1f %%\n", ln.c_str(),
                    100.0 * wrong_share / trials);
        const Vector6d sl = sqrt_lambda_sum / trials;
        std::printf("%-11s mean sqrt(lambda_k) of H~_0 (last round): %.0f %.0f %.0f %.0f %.0f %.0f (tau = %g)\n",
                    ln.c_str(), sl[0], sl[1], sl[2], sl[3], sl[4], sl[5], rw_base.tau);
    }
}

/** 200 factors x 3 candidates linearised on a room frame; H_0 from its points and prior. */
struct ReweightCase
{
    Matrix6d H0 = Matrix6d::Zero();
    double L = 4.0;
    std::vector<StructuralCandidates> factors;
};

ReweightCase makeReweightCase(unsigned seed)
{
    SceneOptions so;
    so.num_lines = 150;
    so.num_planes = 50;
    std::mt19937 rng(seed);
    const SyntheticFrame f = makeSyntheticFrame(so, rng);
    ReweightCase rc;
    rc.H0 = f.prior.information.topLeftCorner<6, 6>();
    for (const auto& p : f.points)
    {
        PointReprojectionFactor pf(f.stereo.left, p.px, p.p_map, p.sigma_px);
        Eigen::Vector2d r;
        Matrix26d J;
        if (pf.linearize(f.T_map_body_true, r, &J)) rc.H0 += J.transpose() * J;
    }
    auto add = [&](const auto& factor, double p, StructuralCandidates& sc) {
        Eigen::VectorXd r;
        Eigen::Matrix<double, -1, 6> J;
        factor.linearize(f.T_map_body_true, r, &J);
        sc.H.push_back(J.transpose() * J);
        sc.probability.push_back(p);
    };
    for (const auto& l : f.lines)
    {
        StructuralCandidates sc;
        for (const auto& c : l.candidates)
            add(PointToLineFactor(f.stereo.left, l.line_px, c.support_map, l.sigma_px), c.probability, sc);
        sc.nominal = nominalCandidate(l.candidates);
        rc.factors.push_back(std::move(sc));
    }
    for (const auto& pl : f.planes)
    {
        StructuralCandidates sc;
        for (const auto& c : pl.candidates)
            add(PointToPlaneFactor(f.stereo.left, pl.points_cam, c.n_map, c.d, pl.sigma_m), c.probability, sc);
        sc.nominal = nominalCandidate(pl.candidates);
        rc.factors.push_back(std::move(sc));
    }
    return rc;
}

const ReweightCase& reweightCase()
{
    static const ReweightCase rc = makeReweightCase(7);
    return rc;
}

void runReweightTiming(const ReweightingOptions& rw)
{
    const ReweightCase& rc = reweightCase();
    ReweightingResult res;
    std::vector<double> ms;
    for (int i = 0; i < 2000; ++i)
    {
        const auto t0 = std::chrono::steady_clock::now();
        computeWeights(rw, rc.H0, rc.L, rc.factors, res);
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    int upweighted = 0;
    for (double w : res.weight) upweighted += w > 1.01;
    std::printf("\n## Reweighting time (mode %s): %zu structural factors x 3 candidates\n",
                valueText(rw, "mode").c_str(), rc.factors.size());
    std::printf("reweighting per frame: median %.4f ms, mean %.4f ms (bound %.3f ms): %s; factors with w > 1.01: %d\n",
                median(ms), mean(ms), kReweightBoundMs, median(ms) <= kReweightBoundMs ? "OK" : "EXCEEDED", upweighted);
}

void BM_Reweighting(benchmark::State& state)
{
    const ReweightCase& rc = reweightCase();
    ReweightingOptions rw;
    ReweightingResult res;
    for (auto _ : state)
    {
        computeWeights(rw, rc.H0, rc.L, rc.factors, res);
        benchmark::DoNotOptimize(res.q.data());
    }
}
BENCHMARK(BM_Reweighting)->Unit(benchmark::kMicrosecond);

int run(int argc, char** argv)
{
    int trials = 200;
    unsigned seed = 1;
    mrpt::config::CConfigFileMemory cfg;
    std::vector<char*> rest = {argv[0]};
    for (int i = 1; i < argc; ++i)
    {
        const std::string a = argv[i];
        if (a == "--trials" && i + 1 < argc)
            trials = std::stoi(argv[++i]);
        else if (a == "--seed" && i + 1 < argc)
            seed = static_cast<unsigned>(std::stoul(argv[++i]));
        else if (a == "--set" && i + 1 < argc)
        {
            const std::string kv = argv[++i];
            const size_t dot = kv.find('.'), eq = kv.find('=');
            core::require(dot != std::string::npos && eq != std::string::npos && dot < eq, "--set " + kv,
                          "expected Section.key=value");
            cfg.write(kv.substr(0, dot), kv.substr(dot + 1, eq - dot - 1), kv.substr(eq + 1));
        }
        else
            rest.push_back(argv[i]);
    }
    core::require(trials >= 1, "--trials", "must be >= 1");
    EstimatorOptions eo;
    ReweightingOptions ro;
    eo.loadFromConfigFile(cfg, "Estimator");
    ro.loadFromConfigFile(cfg, "Reweighting");
    std::printf("# bench_estimation: tau=%g beta=%g kappa=%g, outer=%d inner=%d, loss=%s(%g)\n", ro.tau, ro.beta,
                ro.kappa, eo.outer_iterations, eo.inner_iterations, valueText(eo, "robust_loss").c_str(),
                eo.robust_threshold);
    runAccuracy(trials, seed, eo, ro, false);
    runAccuracy(trials, seed, eo, ro, true);
    runReweightTiming(ro);
    int bargc = static_cast<int>(rest.size());
    benchmark::Initialize(&bargc, rest.data());
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
}  // namespace

int main(int argc, char** argv)
{
    try
    {
        return run(argc, argv);
    }
    catch (const std::exception& e)
    {
        std::fprintf(stderr, "bench_estimation: error: %s\n", e.what());
        return 1;
    }
}
