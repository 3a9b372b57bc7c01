#pragma once
// Shared pieces of bench_frontend: options, per-stage timing with budgets, small statistics.
#include <mrpt/system/CTimeLogger.h>

#include <chrono>
#include <map>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/frontend/frontend.h>
#include <quasiloc/quasi/quasi_options.h>
#include <string>
#include <vector>

namespace quasiloc::bench
{
/** [Bench] section. */
struct BenchOptions : public core::DeclaredOptions
{
    std::string extractors = "orb,sift,akaze,xfeat";  ///< xfeat is skipped (and said so) without a model file
    std::string xfeat_model_path = std::string(QUASILOC_SHARED_DIR) + "/models/xfeat/xfeat_dyn_op11.onnx";
    /** XFeat + LighterGlue is measured when this build has libtorch, this file exists and xfeat is measured. */
    std::string lighterglue_model = std::string(QUASILOC_SHARED_DIR) + "/models/lighterglue/lighterglue_L3_ts.pt";
    /** Existing sim-rawlog folders (comma separated); empty: simulate sim_worlds into sim_root first. */
    std::string sim_dirs;
    std::string sim_worlds = "share/quasiloc/sim/V1_01_easy.ini,share/quasiloc/sim/V2_01_easy.ini";
    std::string sim_root = "/tmp/quasiloc_bench_frontend";  ///< reused when a folder is already complete
    double sim_duration_s = 2.0;
    double sim_start_offset_s = 10.0;  ///< skip the take-off (the MAV is static at the start)
    int frames_per_sequence = 8;       ///< evenly spread over the sequence
    double precision_px = 3.0;         ///< a camera<->quasi match is correct within this (see bench_cross_modal.cpp)
    double perturb_translation_m = 0.10;
    double perturb_rotation_deg = 2.0;
    double cross_modal_window_px = 40;  ///< search window of camera<->quasi point matching (covers the perturbation)
    std::string euroc_dir = std::string(QUASILOC_SHARED_DIR) + "/data/euroc/V1_01_easy_micro";
    int euroc_frames = 40;
    double static_inlier_px = 2.0;  ///< EuRoC micro is static: a temporal match is an inlier if it moved less
    double ransac_px = 1.0;         ///< fundamental-matrix RANSAC threshold (stereo, moving sim frames)
    std::string report_path;        ///< optional Markdown copy of the tables (+ effective INI beside it)

    void declare(core::OptionTable& t) override;
    /** InputError naming `input` for an extractor list that names no or an unknown [Features] type. */
    void check(const std::string& input) const;
    std::vector<std::string> extractorList() const;
};

/** Wall-clock per stage: mean and max in ms, fed to the CTimeLogger as well (for --print-timing). */
class StageTimes
{
   public:
    explicit StageTimes(mrpt::system::CTimeLogger& logger) : logger_(logger) {}
    void add(const std::string& stage, double ms);
    struct Stat
    {
        double sum = 0, max = 0;
        size_t n = 0;
        double mean() const { return n ? sum / double(n) : 0; }
    };
    const std::map<std::string, Stat>& stats() const { return stats_; }

   private:
    mrpt::system::CTimeLogger& logger_;
    std::map<std::string, Stat> stats_;
};

/** Milliseconds since construction. */
class Stopwatch
{
   public:
    Stopwatch() : t0_(std::chrono::steady_clock::now()) {}
    double ms() const
    {
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0_).count();
    }

   private:
    std::chrono::steady_clock::time_point t0_;
};

/** The front-end options for one extractor type (XFeat: with the bench's model path). */
frontend::FrontendOptions withExtractor(const frontend::FrontendOptions& base, const std::string& type,
                                        const BenchOptions& bench);

/** Markdown output collected for stdout and the optional report file. */
struct Report
{
    std::string text;
    void line(const std::string& s);
};

std::string fmt(double v, int decimals = 1);
std::string pct(double num, double den);
/** The budget of a timing row (classical extractors only) and whether the mean meets it; "-" if none applies. */
std::string budgetFor(const std::string& stage, double mean_ms);

/** Part 1: camera <-> quasi on simulated sequences. Part 2: temporal/stereo on the real EuRoC micro frames. */
void runCrossModal(const mrpt::config::CConfigFileBase& cfg, const BenchOptions& bench,
                   const frontend::FrontendOptions& base, const quasi::QuasiOptions& quasi_options,
                   mrpt::system::CTimeLogger& logger, Report& report);
void runEuroc(const BenchOptions& bench, const frontend::FrontendOptions& base, mrpt::system::CTimeLogger& logger,
              Report& report);

}  // namespace quasiloc::bench
