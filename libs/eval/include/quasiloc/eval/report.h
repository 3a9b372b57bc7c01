#pragma once
// Reports of an evaluation run: a Markdown summary (errors in cm and deg, for people), a JSON file
// (SI units, full precision, for scripts) and per-pose / per-query error tables (CSV, for plots).
#include <quasiloc/eval/eval_config.h>
#include <quasiloc/eval/sequence_eval.h>
#include <string>
#include <vector>

namespace quasiloc::eval
{
std::string markdownReport(const std::vector<SequenceReport>& reports, const EvalOptions& opts);
std::string jsonReport(const std::vector<SequenceReport>& reports, const EvalOptions& opts);

/** Tracking:
 * t_est,t_gt,dt_s,trans_err_m,rot_err_deg[,trans_err_se3_m,rot_err_se3_deg,trans_err_sim3_m,rot_err_sim3_deg] (t_gt =
 * t_est with interpolated ground truth). Localization: t,status,trans_err_m,rot_err_deg (errors empty unless
 * localized). */
std::string errorsCsv(const SequenceReport& report);

}  // namespace quasiloc::eval
