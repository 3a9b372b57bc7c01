// The JSON and CSV reports (markdown in report.cpp).
#include <cmath>
#include <cstdio>
#include <quasiloc/eval/json_writer.h>
#include <quasiloc/eval/report.h>
#include <sstream>

namespace quasiloc::eval
{
namespace
{
void writeStats(JsonWriter& j, const std::string& key, const ErrorStats& s)
{
    j.key(key).beginObject();
    j.key("count").value(s.count);
    j.key("rmse").value(s.rmse);
    j.key("mean").value(s.mean);
    j.key("median").value(s.median);
    j.key("max").value(s.max);
    j.key("min").value(s.min);
    j.key("std").value(s.std);
    j.endObject();
}

void writeDoubles(JsonWriter& j, const std::string& key, const std::vector<double>& v)
{
    j.key(key).beginArray();
    for (double x : v) j.value(x);
    j.endArray();
}

void writeTransform(JsonWriter& j, const Similarity3& S)
{
    const Eigen::Quaterniond q(S.R);
    const Eigen::AngleAxisd aa(S.R);
    j.key("transform").beginObject();
    j.key("frames").value("T_gtworld_estworld: p_gt = scale * R * p_est + t");
    writeDoubles(j, "translation_m", {S.t.x(), S.t.y(), S.t.z()});
    writeDoubles(j, "quaternion_wxyz", {q.w(), q.x(), q.y(), q.z()});
    j.key("rotation_deg").value(aa.angle() * 180.0 / M_PI);
    j.key("scale").value(S.scale);
    j.key("degenerate").value(S.degenerate);
    j.key("matrix").beginArray();
    const Eigen::Matrix4d M = S.matrix();
    for (int r = 0; r < 4; ++r)
    {
        j.beginArray();
        for (int c = 0; c < 4; ++c) j.value(M(r, c));
        j.endArray();
    }
    j.endArray();
    j.endObject();
}

void writeAte(JsonWriter& j, const std::string& key, const AteResult& a)
{
    j.key(key).beginObject();
    j.key("alignment").value(toString(a.alignment));
    if (a.alignment != Alignment::None) writeTransform(j, a.transform);
    writeStats(j, "translation_m", a.trans_m);
    writeStats(j, "rotation_deg", a.rot_deg);
    j.endObject();
}

std::string rpeKey(const RpeDelta& d)
{
    return d.unit == RpeUnit::Metres ? "rpe_per_m" : d.unit == RpeUnit::Seconds ? "rpe_per_s" : "rpe_per_frames";
}

void writeTracking(JsonWriter& j, const TrackingReport& t)
{
    // Headline figures first, flat, for scripts; the full statistics follow.
    j.key("ate_rmse_m").value(t.ate.trans_m.rmse);
    j.key("ate_rot_rmse_deg").value(t.ate.rot_deg.rmse);
    if (t.ate_se3) j.key("ate_se3_rmse_m").value(t.ate_se3->trans_m.rmse);
    if (t.ate_sim3)
        j.key("ate_sim3_rmse_m").value(t.ate_sim3->trans_m.rmse).key("sim3_scale").value(t.ate_sim3->transform.scale);
    for (const RpeResult& p : t.rpe) j.key(rpeKey(p.delta) + "_trans_rmse_m").value(p.trans_m.rmse);
    j.key("association").beginObject();
    j.key("ground_truth").value(t.lookup == GroundTruthLookup::Interpolated ? "interpolated" : "nearest");
    j.key("matched").value(t.association.matches.size());
    j.key("unmatched_estimate").value(t.association.unmatched_est.size());
    j.key("unmatched_groundtruth").value(t.association.unmatched_gt);
    j.key("max_abs_dt_s").value(t.association.max_abs_dt_s);
    j.endObject();
    writeAte(j, "ate", t.ate);
    if (t.ate_se3) writeAte(j, "ate_se3", *t.ate_se3);
    if (t.ate_sim3) writeAte(j, "ate_sim3", *t.ate_sim3);
    for (const RpeResult& p : t.rpe)
    {
        j.key(rpeKey(p.delta)).beginObject();
        j.key("delta").value(p.delta.value).key("delta_unit").value(toString(p.delta.unit));
        j.key("estimate_alignment").value(toString(t.rpe_alignment));
        writeStats(j, "translation_m", p.trans_m);
        writeStats(j, "rotation_deg", p.rot_deg);
        j.endObject();
    }
}

void writeLocalization(JsonWriter& j, const LocalizationResult& l, bool have_query_list)
{
    j.key("queries").beginObject();
    j.key("has_query_list").value(have_query_list);
    j.key("total").value(l.num_queries);
    j.key("with_groundtruth").value(l.num_evaluated);
    j.key("localized").value(l.num_localized);
    j.key("not_localized").value(l.num_evaluated - l.num_localized);
    j.key("no_groundtruth").value(l.num_no_ground_truth);
    j.endObject();
    j.key("mate_m").value(l.trans_m.mean);
    writeStats(j, "translation_m", l.trans_m);
    writeStats(j, "rotation_deg", l.rot_deg);
    j.key("recall").beginArray();
    for (const auto& e : l.recall)
    {
        j.beginObject();
        j.key("threshold_m").value(e.threshold.trans_m);
        j.key("threshold_deg").value(e.threshold.rot_deg);  // null: no rotation bound
        j.key("count").value(e.count);
        j.key("recall").value(e.recall);
        j.key("mate_within_m").value(e.trans_m.mean);
        j.endObject();
    }
    j.endArray();
}

void writeSettings(JsonWriter& j, const EvalOptions& o)
{
    j.key("settings").beginObject();
    j.key("max_dt_s").value(o.max_dt_s);
    j.key("association").value(o.association == GroundTruthLookup::Interpolated ? "interpolated" : "nearest");
    j.key("align").value(toString(o.align));
    j.key("rpe_delta_m").value(o.rpe_delta_m);
    j.key("rpe_delta_s").value(o.rpe_delta_s);
    j.key("rpe_delta_frames").value(o.rpe_delta_frames);
    writeDoubles(j, "recall_thresholds_m", o.recall_thresholds_m);
    writeDoubles(j, "recall_thresholds_deg", o.recall_thresholds_deg);
    j.endObject();
}
}  // namespace

std::string jsonReport(const std::vector<SequenceReport>& reports, const EvalOptions& opts)
{
    JsonWriter j;
    j.beginObject();
    j.key("tool").value("quasiloc-eval");
    j.key("units").value("translations in metres, rotations in degrees, times in seconds");
    writeSettings(j, opts);
    j.key("sequences").beginArray();
    for (const auto& r : reports)
    {
        const SequenceOptions& s = r.sequence.options;
        j.beginObject();
        j.key("name").value(r.sequence.name);
        j.key("kind").value(toString(s.kind));
        j.key("estimate_file").value(s.estimate);
        j.key("groundtruth_file").value(s.groundtruth);
        j.key("queries_file").value(s.queries);
        j.key("num_estimate_poses").value(r.num_est);
        j.key("num_groundtruth_poses").value(r.num_gt);
        j.key("duplicates_dropped_estimate").value(r.duplicates_est);
        j.key("duplicates_dropped_groundtruth").value(r.duplicates_gt);
        if (r.kind == SequenceKind::Tracking)
            writeTracking(j, r.tracking);
        else
            writeLocalization(j, r.localization, r.have_query_list);
        j.endObject();
    }
    j.endArray();
    j.endObject();
    return j.str();
}

std::string errorsCsv(const SequenceReport& r)
{
    std::ostringstream out;
    char buf[256];
    if (r.kind == SequenceKind::Localization)
    {
        out << "t,status,trans_err_m,rot_err_deg\n";
        for (const auto& q : r.localization.queries)
        {
            const bool ok = q.status == QueryStatus::Localized;
            std::snprintf(buf, sizeof(buf), "%.9f,%s,", q.t, toString(q.status).c_str());
            out << buf;
            if (ok) std::snprintf(buf, sizeof(buf), "%.6f,%.6f", q.trans_err_m, q.rot_err_deg);
            out << (ok ? buf : ",") << "\n";
        }
        return out.str();
    }
    const TrackingReport& t = r.tracking;
    const bool aligned = t.ate_se3 && t.ate_sim3;
    out << "t_est,t_gt,dt_s,trans_err_m,rot_err_deg"
        << (aligned ? ",trans_err_se3_m,rot_err_se3_deg,trans_err_sim3_m,rot_err_sim3_deg" : "") << "\n";
    for (size_t i = 0; i < t.pairs.size(); ++i)
    {
        std::snprintf(buf, sizeof(buf), "%.9f,%.9f,%.9f,%.6f,%.6f", t.pairs[i].t_est, t.pairs[i].t_gt,
                      t.pairs[i].t_est - t.pairs[i].t_gt, t.ate.trans_errors_m[i], t.ate.rot_errors_deg[i]);
        out << buf;
        if (aligned)
        {
            std::snprintf(buf, sizeof(buf), ",%.6f,%.6f,%.6f,%.6f", t.ate_se3->trans_errors_m[i],
                          t.ate_se3->rot_errors_deg[i], t.ate_sim3->trans_errors_m[i], t.ate_sim3->rot_errors_deg[i]);
            out << buf;
        }
        out << "\n";
    }
    return out.str();
}

}  // namespace quasiloc::eval
