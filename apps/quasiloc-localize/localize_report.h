#pragma once
// quasiloc-localize's results: one row per query and mode, the per-mode summary (Recall, mATE, stage times through
// libs/eval) and its files (<mode>.csv, summary.md, summary.json).
#include <quasiloc/eval/error_stats.h>
#include <quasiloc/reloc/localizer.h>
#include <string>
#include <vector>

namespace quasiloc::app
{
struct QueryRow
{
    double t = 0;
    reloc::LocalizationReport report;
    bool has_gt = false;
    double err_m = NAN, err_deg = NAN;
};

struct ModeSummary
{
    std::string mode;
    size_t queries = 0;
    size_t evaluated = 0;          ///< queries with ground truth: the recall's denominator
    size_t localized = 0;          ///< queries localized (with or without ground truth)
    size_t wrong = 0;              ///< localized but > 1 m off the ground truth
    double recall[3] = {0, 0, 0};  ///< within 0.1, 0.3 and 1.0 m
    eval::ErrorStats ate_m, ms_total, ms_extract, ms_retrieval, ms_rerank, ms_pnp;
};

ModeSummary summarize(const std::string& mode, const std::vector<QueryRow>& rows);
std::string csvOf(const std::vector<QueryRow>& rows);
std::string markdownOf(const std::vector<ModeSummary>& modes, const std::string& what);
std::string jsonOf(const std::vector<ModeSummary>& modes, const std::string& what);

}  // namespace quasiloc::app
