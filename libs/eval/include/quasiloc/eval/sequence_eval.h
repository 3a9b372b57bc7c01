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
    Association association;
    std::vector<PosePair> pairs;         ///< associated poses, raw (map frame)
    AteResult ate;                       ///< unaligned, always
    std::optional<AteResult> ate_aligned;///< when [Eval] align != none
    RpeResult rpe;                       ///< on the aligned estimate if aligned (SE(3) does not change it)
};

struct SequenceReport
{
    NamedSequence sequence;
    SequenceKind kind = SequenceKind::Tracking;
    size_t num_est = 0, num_gt = 0;  ///< poses read (after dropping duplicates)
    size_t duplicates_est = 0, duplicates_gt = 0;  ///< poses with a repeated timestamp, dropped
    bool have_query_list = false;
    TrackingReport tracking;          ///< kind == Tracking
    LocalizationResult localization;  ///< kind == Localization
};

/** InputError for unreadable files, or for a tracking sequence in which no pose associates. */
SequenceReport evaluateSequence(const NamedSequence& seq, const EvalOptions& opts);

}  // namespace quasiloc::eval
