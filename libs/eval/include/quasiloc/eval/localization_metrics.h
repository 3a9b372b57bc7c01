#pragma once
// Evaluation of global localization queries: each query (an image at time t) either yields a pose or
// "not localized". Recall at a threshold = (localized queries with translation error <= thr_m [and rotation
// error <= thr_deg]) / (queries that have ground truth); not-localized queries count in the denominator.
//
// Inputs: the localizer's TUM file holds the localized queries only; the list of all queried timestamps
// comes from a query file (readQueryTimestamps). Without a query file every estimate is a query (nothing
// counts as not localized).
#include <limits>
#include <mrpt/poses/CPose3D.h>
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/eval/error_stats.h>
#include <string>
#include <vector>

namespace quasiloc::eval
{
/** A query file: one timestamp (seconds) per line; blank lines and lines starting with '#' are ignored;
 *  anything after the first number on a line (separated by space, tab or comma) is ignored, so the first
 *  column of a CSV or TUM file also works. InputError naming file:line for a non-number, non-finite or
 *  duplicate timestamp, or an empty list. Returned sorted. */
std::vector<double> readQueryTimestamps(const std::string& path);

enum class QueryStatus
{
    Localized,
    NotLocalized,
    NoGroundTruth  ///< no ground-truth pose within max_dt_s: not evaluated, not in the denominator
};
std::string toString(QueryStatus s);  ///< "localized", "not_localized", "no_ground_truth"

struct QueryResult
{
    double t = 0;  ///< the query timestamp
    QueryStatus status = QueryStatus::NotLocalized;
    bool localized = false;        ///< the localizer gave a pose (also for NoGroundTruth queries)
    mrpt::poses::CPose3D est, gt;  ///< T_map_cam; gt valid unless NoGroundTruth, est valid if localized
    double trans_err_m = std::numeric_limits<double>::quiet_NaN();  ///< Localized only
    double rot_err_deg = std::numeric_limits<double>::quiet_NaN();
};

struct RecallThreshold
{
    double trans_m = 0;
    double rot_deg = std::numeric_limits<double>::infinity();  ///< infinity: translation only
};

struct RecallEntry
{
    RecallThreshold threshold;
    size_t count = 0;    ///< localized queries within the threshold
    double recall = 0;   ///< count / num_evaluated (NaN when nothing is evaluated)
    ErrorStats trans_m;  ///< translation errors of those within the threshold (mean = "inlier mATE")
};

struct LocalizationResult
{
    std::vector<QueryResult> queries;  ///< sorted by time
    size_t num_queries = 0;            ///< all queries
    size_t num_evaluated = 0;          ///< queries with ground truth: the denominator of recall
    size_t num_localized = 0;          ///< evaluated queries that got a pose
    size_t num_no_ground_truth = 0;
    ErrorStats trans_m, rot_deg;      ///< over the evaluated localized queries; trans_m.mean = mATE
    std::vector<RecallEntry> recall;  ///< one per threshold, in the given order
};

/** Query timestamps are matched to estimate timestamps within `query_match_tol_s` (they come from the same
 *  program, so the default is tight) and to ground truth within `max_dt_s`, both one-to-one.
 *  InputError (naming `estimate_name`) when an estimate pose matches no query. */
LocalizationResult evaluateLocalization(const core::Trajectory& est, const core::Trajectory& gt,
                                        const std::vector<double>& query_times, bool have_query_list, double max_dt_s,
                                        const std::vector<RecallThreshold>& thresholds,
                                        const std::string& estimate_name, double query_match_tol_s = 1e-3);

}  // namespace quasiloc::eval
