#include <algorithm>
#include <cmath>
#include <fstream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/eval/association.h>
#include <quasiloc/eval/localization_metrics.h>
#include <sstream>

namespace quasiloc::eval
{
std::vector<double> readQueryTimestamps(const std::string& path)
{
    std::ifstream in(path);
    core::require(in.good(), path, "query timestamp file not found or unreadable");
    std::vector<std::pair<double, int>> times;  // (t, line)
    std::string line;
    int line_no = 0;
    while (std::getline(in, line))
    {
        ++line_no;
        const auto first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#') continue;
        const auto end = line.find_first_of(" \t\r,", first);
        const std::string token = line.substr(first, end == std::string::npos ? std::string::npos : end - first);
        const std::string where = path + ":" + std::to_string(line_no);
        size_t used = 0;
        double t = 0;
        try
        {
            t = std::stod(token, &used);
        }
        catch (const std::exception&)
        {
            used = 0;
        }
        core::require(used == token.size() && !token.empty(), where, "expected a timestamp, got '" + token + "'");
        core::require(std::isfinite(t), where, "non-finite timestamp");
        times.emplace_back(t, line_no);
    }
    core::require(!times.empty(), path, "no query timestamps in the file");
    std::stable_sort(times.begin(), times.end());
    std::vector<double> out;
    for (size_t i = 0; i < times.size(); ++i)
    {
        core::require(i == 0 || times[i].first > times[i - 1].first, path + ":" + std::to_string(times[i].second),
                      "duplicate query timestamp");
        out.push_back(times[i].first);
    }
    return out;
}

std::string toString(QueryStatus s)
{
    switch (s)
    {
        case QueryStatus::Localized: return "localized";
        case QueryStatus::NotLocalized: return "not_localized";
        case QueryStatus::NoGroundTruth: return "no_ground_truth";
    }
    return "?";
}

namespace
{
std::vector<double> timesOf(const core::Trajectory& traj)
{
    std::vector<double> t;
    for (const auto& p : traj.poses) t.push_back(p.t);
    return t;
}

std::vector<RecallEntry> recallAt(const std::vector<QueryResult>& queries, size_t num_evaluated,
                                  const std::vector<RecallThreshold>& thresholds)
{
    std::vector<RecallEntry> out;
    for (const auto& thr : thresholds)
    {
        RecallEntry e;
        e.threshold = thr;
        std::vector<double> within;
        for (const auto& q : queries)
            if (q.status == QueryStatus::Localized && q.trans_err_m <= thr.trans_m && q.rot_err_deg <= thr.rot_deg)
                within.push_back(q.trans_err_m);
        e.count = within.size();
        e.recall = num_evaluated ? static_cast<double>(e.count) / static_cast<double>(num_evaluated)
                                 : std::numeric_limits<double>::quiet_NaN();
        e.trans_m = computeStats(within);
        out.push_back(e);
    }
    return out;
}
}  // namespace

LocalizationResult evaluateLocalization(const core::Trajectory& est, const core::Trajectory& gt,
                                        const std::vector<double>& query_times_in, bool have_query_list,
                                        double max_dt_s, const std::vector<RecallThreshold>& thresholds,
                                        const std::string& estimate_name, double query_match_tol_s)
{
    const std::vector<double> est_times = timesOf(est);
    const std::vector<double> query_times = have_query_list ? query_times_in : est_times;

    // Which queries were localized: each estimate must be the answer to exactly one query.
    const Association est_to_query = associateByTime(est_times, query_times, query_match_tol_s);
    if (!est_to_query.unmatched_est.empty())
    {
        char buf[64];
        std::snprintf(buf, sizeof(buf), "%.9f", est_times[est_to_query.unmatched_est.front()]);
        throw core::InputError(estimate_name, std::to_string(est_to_query.unmatched_est.size()) +
                                                  " estimate pose(s) match no query timestamp (first at t=" + buf +
                                                  "): the estimate and the query list disagree");
    }
    std::vector<long> est_of_query(query_times.size(), -1);
    for (const Match& m : est_to_query.matches) est_of_query[m.gt_index] = static_cast<long>(m.est_index);

    const Association query_to_gt = associateByTime(query_times, timesOf(gt), max_dt_s);
    std::vector<long> gt_of_query(query_times.size(), -1);
    for (const Match& m : query_to_gt.matches) gt_of_query[m.est_index] = static_cast<long>(m.gt_index);

    LocalizationResult r;
    r.num_queries = query_times.size();
    std::vector<double> trans, rot;
    for (size_t q = 0; q < query_times.size(); ++q)
    {
        QueryResult qr;
        qr.t = query_times[q];
        qr.localized = est_of_query[q] >= 0;
        if (qr.localized) qr.est = est.poses[static_cast<size_t>(est_of_query[q])].pose;
        if (gt_of_query[q] < 0)
        {
            qr.status = QueryStatus::NoGroundTruth;
            ++r.num_no_ground_truth;
        }
        else
        {
            qr.gt = gt.poses[static_cast<size_t>(gt_of_query[q])].pose;
            ++r.num_evaluated;
            qr.status = qr.localized ? QueryStatus::Localized : QueryStatus::NotLocalized;
        }
        if (qr.status == QueryStatus::Localized)
        {
            ++r.num_localized;
            qr.trans_err_m = core::translationDistance(qr.est, qr.gt);
            qr.rot_err_deg = core::rotationDistanceRad(qr.gt, qr.est) * 180.0 / M_PI;
            trans.push_back(qr.trans_err_m);
            rot.push_back(qr.rot_err_deg);
        }
        r.queries.push_back(qr);
    }
    r.trans_m = computeStats(trans);
    r.rot_deg = computeStats(rot);
    r.recall = recallAt(r.queries, r.num_evaluated, thresholds);
    return r;
}

}  // namespace quasiloc::eval
