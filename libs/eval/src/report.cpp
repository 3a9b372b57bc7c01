#include <cmath>
#include <cstdio>
#include <quasiloc/eval/json_writer.h>
#include <quasiloc/eval/report.h>
#include <sstream>

namespace quasiloc::eval
{
namespace
{
std::string fmt(double v, const char* format)
{
    if (!std::isfinite(v)) return "-";
    char buf[64];
    std::snprintf(buf, sizeof(buf), format, v);
    std::string s = buf;
    // "-0.00" (a tiny negative value rounded) reads like a sign error: print "0.00".
    if (s[0] == '-' && s.find_first_of("123456789") == std::string::npos) s.erase(0, 1);
    return s;
}
// Sensible precision for people: 0.01 cm (0.1 mm) and 0.001 deg; the JSON has full precision.
std::string cm(double m) { return fmt(100.0 * m, "%.2f"); }
std::string deg(double d) { return fmt(d, "%.3f"); }
std::string percent(double r) { return fmt(100.0 * r, "%.1f %%"); }

std::string thresholdLabel(const RecallThreshold& t)
{
    std::string s = "≤" + fmt(100.0 * t.trans_m, "%g") + " cm";
    if (std::isfinite(t.rot_deg)) s += ", " + fmt(t.rot_deg, "%g") + "°";
    return s;
}

std::string alignmentName(Alignment a) { return a == Alignment::Sim3 ? "Sim(3)" : "SE(3)"; }

/** The ATE of `alignment` of a tracking report, if computed. */
const AteResult* ateOf(const TrackingReport& t, Alignment alignment)
{
    if (alignment == Alignment::None) return &t.ate;
    const auto& a = alignment == Alignment::SE3 ? t.ate_se3 : t.ate_sim3;
    return a ? &*a : nullptr;
}

void ateTable(std::ostringstream& md, const std::vector<SequenceReport>& reports, Alignment alignment)
{
    md << "| sequence | est | gt | matched | unmatched est | ATE RMSE [cm] | mean [cm] | median [cm] | std [cm] | "
          "min [cm] | max [cm] | rot RMSE [deg] | rot mean [deg] | rot median [deg] | rot max [deg] |\n"
       << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& r : reports)
    {
        if (r.kind != SequenceKind::Tracking) continue;
        const TrackingReport& t = r.tracking;
        const AteResult* a = ateOf(t, alignment);
        const ErrorStats none;
        const ErrorStats& e = a ? a->trans_m : none;
        const ErrorStats& o = a ? a->rot_deg : none;
        md << "| " << r.sequence.name << " | " << r.num_est << " | " << r.num_gt << " | "
           << t.association.matches.size() << " | " << t.association.unmatched_est.size() << " | " << cm(e.rmse)
           << " | " << cm(e.mean) << " | " << cm(e.median) << " | " << cm(e.std) << " | " << cm(e.min) << " | "
           << cm(e.max) << " | " << deg(o.rmse) << " | " << deg(o.mean) << " | " << deg(o.median) << " | " << deg(o.max)
           << " |\n";
    }
}

void alignmentLines(std::ostringstream& md, const std::vector<SequenceReport>& reports, Alignment alignment)
{
    md << "\n" << alignmentName(alignment) << " alignment T_gtworld_estworld (applied to the estimate):\n";
    for (const auto& r : reports)
    {
        if (r.kind != SequenceKind::Tracking) continue;
        const AteResult* a = ateOf(r.tracking, alignment);
        if (!a)
        {
            md << "- " << r.sequence.name << ": none (fewer than 3 associated poses)\n";
            continue;
        }
        const Similarity3& S = a->transform;
        const Eigen::AngleAxisd aa(S.R);
        md << "- " << r.sequence.name << ": t = [" << fmt(S.t.x(), "%.4f") << ", " << fmt(S.t.y(), "%.4f") << ", "
           << fmt(S.t.z(), "%.4f") << "] m, rotation " << deg(aa.angle() * 180.0 / M_PI) << " deg about ["
           << fmt(aa.axis().x(), "%.3f") << ", " << fmt(aa.axis().y(), "%.3f") << ", " << fmt(aa.axis().z(), "%.3f")
           << "], scale " << fmt(S.scale, "%.6f")
           << (S.degenerate ? " — WARNING: degenerate (collinear positions), rotation not determined" : "") << "\n";
    }
}

/** "per 1 m", "per 1 s", "per 5 associated poses". */
std::string deltaName(const RpeDelta& d)
{
    const std::string v = fmt(d.value, "%g");
    return "per " + v + (d.unit == RpeUnit::Metres ? " m" : d.unit == RpeUnit::Seconds ? " s" : " associated poses");
}

/** deltaName and how the pairs are chosen. */
std::string deltaLabel(const RpeDelta& d)
{
    const std::string v = fmt(d.value, "%g");
    switch (d.unit)
    {
        case RpeUnit::Metres:
            return deltaName(d) + " of path (evo_rpe --delta " + v + " --delta_unit m: consecutive pairs)";
        case RpeUnit::Seconds:
            return deltaName(d) + " (TUM evaluate_rpe.py --fixed_delta --delta " + v + " --delta_unit s: every pose)";
        case RpeUnit::Frames: return deltaName(d) + " (every pose)";
    }
    return "?";
}

void rpeTables(std::ostringstream& md, const std::vector<SequenceReport>& reports, const EvalOptions& opts)
{
    const std::vector<RpeDelta> deltas = opts.rpeDeltas();
    for (size_t k = 0; k < deltas.size(); ++k)
    {
        md << "\n## Tracking: RPE " << deltaLabel(deltas[k])
           << (opts.align == Alignment::Sim3 ? ", Sim(3)-scaled estimate" : "") << "\n\n"
           << "| sequence | pairs | trans RMSE [cm] | mean [cm] | median [cm] | std [cm] | min [cm] | max [cm] | "
              "rot RMSE [deg] | mean [deg] | median [deg] | max [deg] |\n"
           << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
        for (const auto& r : reports)
        {
            if (r.kind != SequenceKind::Tracking) continue;
            const RpeResult& p = r.tracking.rpe.at(k);
            md << "| " << r.sequence.name << " | " << p.trans_m.count << " | " << cm(p.trans_m.rmse) << " | "
               << cm(p.trans_m.mean) << " | " << cm(p.trans_m.median) << " | " << cm(p.trans_m.std) << " | "
               << cm(p.trans_m.min) << " | " << cm(p.trans_m.max) << " | " << deg(p.rot_deg.rmse) << " | "
               << deg(p.rot_deg.mean) << " | " << deg(p.rot_deg.median) << " | " << deg(p.rot_deg.max) << " |\n";
        }
    }
}

void localizationTable(std::ostringstream& md, const std::vector<SequenceReport>& reports, const EvalOptions& opts)
{
    const auto thresholds = opts.recallThresholds();
    if (thresholds.empty()) return;  // check() forbids it; keep the table code simple
    md << "\n## Localization queries (map frame, no alignment)\n\n| sequence | queries | with gt | localized |";
    for (const auto& t : thresholds) md << " recall " << thresholdLabel(t) << " |";
    md << " mATE [cm] (all localized) | mATE [cm] (" << thresholdLabel(thresholds.back())
       << ") | median [cm] | rot mean [deg] |\n|---|---:|---:|---:|";
    for (size_t i = 0; i < thresholds.size() + 4; ++i) md << "---:|";
    md << "\n";
    for (const auto& r : reports)
    {
        if (r.kind != SequenceKind::Localization) continue;
        const LocalizationResult& l = r.localization;
        md << "| " << r.sequence.name << " | " << l.num_queries << " | " << l.num_evaluated << " | " << l.num_localized
           << " |";
        for (const auto& e : l.recall) md << " " << percent(e.recall) << " |";
        const double mate_within = l.recall.empty() ? NAN : l.recall.back().trans_m.mean;
        md << " " << cm(l.trans_m.mean) << " | " << cm(mate_within) << " | " << cm(l.trans_m.median) << " | "
           << deg(l.rot_deg.mean) << " |\n";
    }
    md << "\nRecall = localized queries within the threshold / queries with ground truth (not-localized queries "
          "count as failures). mATE = mean translation error of the localized queries.\n";
}

void notes(std::ostringstream& md, const std::vector<SequenceReport>& reports)
{
    std::ostringstream n;
    for (const auto& r : reports)
    {
        if (r.duplicates_est || r.duplicates_gt)
            n << "- " << r.sequence.name << ": dropped poses with a repeated timestamp: " << r.duplicates_est
              << " in the estimate, " << r.duplicates_gt << " in the ground truth\n";
        if (r.kind == SequenceKind::Localization && !r.have_query_list)
            n << "- " << r.sequence.name << ": no query list: every estimate counts as a query, so the recall "
              << "ignores queries that were not localized\n";
        if (r.kind == SequenceKind::Localization && r.localization.num_no_ground_truth)
            n << "- " << r.sequence.name << ": " << r.localization.num_no_ground_truth
              << " queries have no ground truth within max_dt_s and are not evaluated\n";
        if (r.kind == SequenceKind::Tracking)
            for (const RpeResult& p : r.tracking.rpe)
                if (p.trans_m.count == 0)
                    n << "- " << r.sequence.name << ": no RPE pair " << deltaName(p.delta)
                      << " (trajectory shorter than the delta?)\n";
        if (r.kind == SequenceKind::Tracking && !r.tracking.ate_se3)
            n << "- " << r.sequence.name << ": fewer than 3 associated poses: no aligned ATE\n";
    }
    if (!n.str().empty()) md << "\n## Notes\n\n" << n.str();
}
}  // namespace

std::string markdownReport(const std::vector<SequenceReport>& reports, const EvalOptions& opts)
{
    bool any_tracking = false, any_loc = false;
    for (const auto& r : reports) (r.kind == SequenceKind::Tracking ? any_tracking : any_loc) = true;
    std::ostringstream md;
    md << "# quasiloc-eval report\n\n"
       << (opts.association == GroundTruthLookup::Interpolated
               ? "Ground truth interpolated at each estimate time (the nearer sample within "
               : "Poses associated one-to-one by timestamp (|dt| ≤ ")
       << fmt(opts.max_dt_s, "%g") << " s). Errors are in the map frame unless an alignment is named.\n";
    if (any_tracking)
    {
        md << "\n## Tracking: ATE, map frame (no alignment)\n\n";
        ateTable(md, reports, Alignment::None);
        md << "\n## Tracking: ATE after SE(3) alignment (Umeyama)\n\n";
        ateTable(md, reports, Alignment::SE3);
        md << "\n## Tracking: ATE after Sim(3) alignment (Umeyama with scale, for monocular estimates)\n\n";
        ateTable(md, reports, Alignment::Sim3);
        alignmentLines(md, reports, Alignment::SE3);
        alignmentLines(md, reports, Alignment::Sim3);
        rpeTables(md, reports, opts);
    }
    if (any_loc) localizationTable(md, reports, opts);
    notes(md, reports);
    return md.str();
}

}  // namespace quasiloc::eval
