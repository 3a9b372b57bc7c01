#include "localize_report.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <quasiloc/eval/json_writer.h>
#include <sstream>

namespace quasiloc::app
{
namespace
{
const double kThresholds[] = {0.1, 0.3, 1.0};
}  // namespace

ModeSummary summarize(const std::string& mode, const std::vector<QueryRow>& rows)
{
    ModeSummary s;
    s.mode = mode;
    s.queries = rows.size();
    std::vector<double> ate, tot, ex, re, rr, pnp;
    size_t within[3] = {0, 0, 0};
    for (const auto& q : rows)
    {
        tot.push_back(q.report.ms.total);
        ex.push_back(q.report.ms.extract);
        re.push_back(q.report.ms.retrieval);
        rr.push_back(q.report.ms.rerank);
        pnp.push_back(q.report.ms.pnp);
        s.localized += q.report.localized ? 1 : 0;
        if (!q.has_gt) continue;
        ++s.evaluated;
        if (!q.report.localized) continue;
        for (int k = 0; k < 3; ++k) within[k] += q.err_m <= kThresholds[k] ? 1 : 0;
        if (q.err_m <= kThresholds[2])
            ate.push_back(q.err_m);
        else
            ++s.wrong;
    }
    for (int k = 0; k < 3; ++k) s.recall[k] = s.evaluated ? 100.0 * double(within[k]) / double(s.evaluated) : NAN;
    s.ate_m = eval::computeStats(ate);
    s.ms_total = eval::computeStats(tot);
    s.ms_extract = eval::computeStats(ex);
    s.ms_retrieval = eval::computeStats(re);
    s.ms_rerank = eval::computeStats(rr);
    s.ms_pnp = eval::computeStats(pnp);
    return s;
}

std::string csvOf(const std::vector<QueryRow>& rows)
{
    std::ostringstream csv;
    csv << "t,localized,reason,inliers,correspondences,retried,groups_reranked,err_m,err_deg,ms_extract,ms_retrieval,"
           "ms_rerank,ms_pnp,ms_total\n";
    for (const auto& q : rows)
    {
        const auto& r = q.report;
        int reranked = 0;
        for (const auto& g : r.groups) reranked += g.matched >= 0 ? 1 : 0;
        std::string reason = r.reason;
        std::replace(reason.begin(), reason.end(), ',', ';');
        csv << std::setprecision(17) << q.t << std::setprecision(6) << "," << r.localized << "," << reason << ","
            << r.inliers << "," << r.correspondences << "," << r.retried << "," << reranked << "," << q.err_m << ","
            << q.err_deg << "," << r.ms.extract << "," << r.ms.retrieval << "," << r.ms.rerank << "," << r.ms.pnp << ","
            << r.ms.total << "\n";
    }
    return csv.str();
}

std::string markdownOf(const std::vector<ModeSummary>& modes, const std::string& what)
{
    std::ostringstream md;
    md << std::fixed << std::setprecision(1) << "# quasiloc-localize summary\n\n"
       << what << "\n\n"
       << "| mode | queries | with ground truth | localized | Recall@0.1 m | Recall@0.3 m | Recall@1.0 m | mATE (<= 1 "
          "m) "
          "[cm] | wrong (> 1 m) | median ms | p-max ms | extract | retrieval | rerank | PnP |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    bool any_ground_truth = false;
    for (const auto& s : modes)
    {
        md << "| " << s.mode << " | " << s.queries << " | " << s.evaluated << " | " << s.localized << " | ";
        // Without ground truth there is no error: "-" rather than a 0 that reads as a result.
        if (s.evaluated > 0)
        {
            any_ground_truth = true;
            md << s.recall[0] << " % | " << s.recall[1] << " % | " << s.recall[2] << " % | " << 100 * s.ate_m.mean
               << " | " << s.wrong << " | ";
        }
        else
            md << "- | - | - | - | - | ";
        md << s.ms_total.median << " | " << s.ms_total.max << " | " << s.ms_extract.median << " | "
           << s.ms_retrieval.median << " | " << s.ms_rerank.median << " | " << s.ms_pnp.median << " |\n";
    }
    md << "\nRecall = localized within the threshold / queries with ground truth (not-localized queries count). mATE: "
          "mean translation error of the queries localized within 1 m. Stage times are medians (ms, wall).\n";
    if (!any_ground_truth) md << "No query has ground truth: localized counts every localized query; no error.\n";
    return md.str();
}

std::string jsonOf(const std::vector<ModeSummary>& modes, const std::string& what)
{
    eval::JsonWriter j;
    j.beginObject().key("what").value(what).key("modes").beginArray();
    for (const auto& s : modes)
    {
        j.beginObject().key("mode").value(s.mode).key("queries").value(s.queries).key("evaluated").value(s.evaluated);
        j.key("localized").value(s.localized);
        if (s.evaluated > 0)  // the errors exist only against ground truth: omitted, not null, without it
        {
            j.key("wrong_over_1m").value(s.wrong);
            j.key("recall_0.1m").value(s.recall[0]).key("recall_0.3m").value(s.recall[1]);
            j.key("recall_1.0m").value(s.recall[2]).key("mate_m").value(s.ate_m.mean);
        }
        j.key("median_ms").value(s.ms_total.median).key("max_ms").value(s.ms_total.max);
        j.key("median_ms_extract").value(s.ms_extract.median).key("median_ms_retrieval").value(s.ms_retrieval.median);
        j.key("median_ms_rerank").value(s.ms_rerank.median).key("median_ms_pnp").value(s.ms_pnp.median);
        j.endObject();
    }
    j.endArray().endObject();
    return j.str() + "\n";
}

}  // namespace quasiloc::app
