#pragma once
// Evaluation of one configured sequence: read the files, associate, compute the metrics of its kind.
#include <optional>
#include <quasiloc/eval/association.h>
#include <quasiloc/eval/eval_config.h>
#include <quasiloc/eval/localization_metrics.h>
#include <quasiloc/eval/trajectory_metrics.h>
#include <string>
#include <vector>

namespace quasiloc::eval
{
struct TrackingReport
{
    GroundTruthLookup lookup = GroundTruthLookup::Nearest;
    Association association;
    std::vector<PosePair> pairs;                ///< associated poses, raw (map frame)
    AteResult ate;                              ///< unaligned (map frame), always
    std::optional<AteResult> ate_se3;           ///< SE(3)-aligned, when >= 3 poses are associated
    std::optional<AteResult> ate_sim3;          ///< Sim(3)-aligned, when >= 3 poses are associated
    Alignment rpe_alignment = Alignment::None;  ///< the estimate the RPE is computed on ([Eval] align)
    std::vector<RpeResult> rpe;                 ///< one per [Eval] RPE delta (EvalOptions::rpeDeltas)
};

struct SequenceReport
{
    NamedSequence sequence;
    SequenceKind kind = SequenceKind::Tracking;
    size_t num_est = 0, num_gt = 0;                ///< poses read (after dropping duplicates)
    size_t duplicates_est = 0, duplicates_gt = 0;  ///< poses with a repeated timestamp, dropped
    bool have_query_list = false;
    TrackingReport tracking;          ///< kind == Tracking
    LocalizationResult localization;  ///< kind == Localization
};

/** InputError for unreadable files, or for a tracking sequence in which no pose associates. */
SequenceReport evaluateSequence(const NamedSequence& seq, const EvalOptions& opts);

}  // namespace quasiloc::eval
