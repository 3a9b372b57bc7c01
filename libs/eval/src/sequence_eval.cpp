#include <quasiloc/core/error.h>
#include <quasiloc/eval/sequence_eval.h>

namespace quasiloc::eval
{
namespace
{
TrackingReport evaluateTracking(const core::Trajectory& est, const core::Trajectory& gt, const EvalOptions& opts,
                                const NamedSequence& seq)
{
    TrackingReport r;
    r.lookup = opts.association;
    if (opts.association == GroundTruthLookup::Interpolated)
        r.pairs = makeInterpolatedPairs(est, gt, opts.max_dt_s, r.association);
    else
    {
        r.association = associate(est, gt, opts.max_dt_s);
        r.pairs = makePairs(est, gt, r.association);
    }
    char dt[32];
    std::snprintf(dt, sizeof(dt), "%g", opts.max_dt_s);
    core::require(!r.association.matches.empty(), "sequence " + seq.name + " (" + seq.options.estimate + ")",
                  "no estimate pose lies within max_dt_s = " + std::string(dt) +
                      " s of a ground-truth pose (different time bases or units?)");
    r.ate = computeAte(r.pairs, Alignment::None);
    if (r.pairs.size() >= 3)
    {
        r.ate_se3 = computeAte(r.pairs, Alignment::SE3);
        r.ate_sim3 = computeAte(r.pairs, Alignment::Sim3);
    }
    // An SE(3) alignment leaves every relative pose, hence the RPE, as it is: only a Sim(3) changes the estimate.
    r.rpe_alignment = opts.align;
    std::vector<PosePair> rpe_pairs = r.pairs;
    if (opts.align == Alignment::Sim3)
    {
        core::require(r.ate_sim3.has_value(), "sequence " + seq.name, "align = sim3 needs at least 3 associated poses");
        rpe_pairs = applySimilarity(r.ate_sim3->transform, r.pairs);
    }
    for (const RpeDelta& d : opts.rpeDeltas()) r.rpe.push_back(computeRpe(rpe_pairs, d));
    return r;
}
}  // namespace

SequenceReport evaluateSequence(const NamedSequence& seq, const EvalOptions& opts)
{
    SequenceReport r;
    r.sequence = seq;
    r.kind = seq.options.kind;
    core::Trajectory est = core::readTum(seq.options.estimate);
    core::Trajectory gt = core::readTum(seq.options.groundtruth);
    r.duplicates_est = dropDuplicateTimestamps(est);
    r.duplicates_gt = dropDuplicateTimestamps(gt);
    r.num_est = est.poses.size();
    r.num_gt = gt.poses.size();
    core::require(!gt.poses.empty(), seq.options.groundtruth, "ground truth has no pose");
    if (r.kind == SequenceKind::Tracking)
    {
        core::require(!est.poses.empty(), seq.options.estimate, "estimate has no pose");
        r.tracking = evaluateTracking(est, gt, opts, seq);
        return r;
    }
    r.have_query_list = !seq.options.queries.empty();
    core::require(r.have_query_list || !est.poses.empty(), seq.options.estimate,
                  "estimate has no pose and no query list is given: nothing to evaluate");
    const std::vector<double> queries =
        r.have_query_list ? readQueryTimestamps(seq.options.queries) : std::vector<double>{};
    r.localization = evaluateLocalization(est, gt, queries, r.have_query_list, opts.max_dt_s, opts.recallThresholds(),
                                          seq.options.estimate);
    return r;
}

}  // namespace quasiloc::eval
