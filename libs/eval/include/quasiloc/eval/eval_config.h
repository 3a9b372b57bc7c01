#pragma once
// Configuration of quasiloc-eval: [Eval] (EvalOptions::declare) and one [Eval.<name>] per sequence
// (SequenceOptions::declare), eval_config.cpp. Example with every key documented: share/quasiloc/eval_example.ini.
// Put comments on their own lines: MRPT's INI reader keeps a "; ..." after a value as part of the value.
//
// The ATE is reported in the map frame (unaligned) first, then after SE(3) and Sim(3) Umeyama alignments; align picks
// the estimate the RPE is computed on (none and se3 give the same RPE; sim3 corrects the scale, for monocular
// estimates). The RPE is reported per rpe_delta_m metres of path, per rpe_delta_s seconds and per rpe_delta_frames
// associated poses, each when > 0 (at least one must be). recall_thresholds_deg is empty (translation only) or has one
// value per recall_thresholds_m entry. Every name in sequence_names has a section [Eval.<name>]; estimate and
// groundtruth are TUM files of T_map_cam; queries (localization only, optional) lists
// every queried timestamp (see readQueryTimestamps).
//
// The command line splits "--set Section.key=value" at the first dot, so "--set Eval.v101.estimate=x.tum"
// arrives as key "v101.estimate" of [Eval]; the loader moves such keys into [Eval.v101].
// Unknown keys, an [Eval.*] section not listed in sequence_names, a listed name without its section, and
// missing files are errors. Other sections are ignored (the INI may serve other programs too).
#include <mrpt/config/CConfigFileBase.h>

#include <quasiloc/core/declared_options.h>
#include <quasiloc/eval/localization_metrics.h>
#include <quasiloc/eval/trajectory_metrics.h>
#include <string>
#include <vector>

namespace quasiloc::eval
{
/** How an estimate pose finds its ground truth. */
enum class GroundTruthLookup
{
    Nearest,      ///< the ground-truth pose nearest in time, one-to-one (TUM associate.py, evo)
    Interpolated  ///< the ground truth interpolated at the estimate's time (what quasiloc-track does for its frames)
};

struct EvalOptions : public core::DeclaredOptions
{
    std::string output_dir = "out/eval";
    double max_dt_s = 0.02;
    GroundTruthLookup association = GroundTruthLookup::Nearest;
    Alignment align = Alignment::None;
    double rpe_delta_m = 1.0;
    double rpe_delta_s = 1.0;
    int rpe_delta_frames = 0;
    std::vector<double> recall_thresholds_m = {0.1, 0.3, 1.0};
    std::vector<double> recall_thresholds_deg;  ///< empty: translation-only recall
    std::vector<std::string> sequence_names;

    void declare(core::OptionTable& t) override;
    /** InputError naming `input` and the key for a bad value. */
    void check(const std::string& input) const;

    /** The RPE deltas that are > 0: metres, seconds, frames, in this order. */
    std::vector<RpeDelta> rpeDeltas() const;
    std::vector<RecallThreshold> recallThresholds() const;
};

enum class SequenceKind
{
    Tracking,     ///< a trajectory (ATE, RPE)
    Localization  ///< the localized queries only (recall)
};
std::string toString(SequenceKind k);

struct SequenceOptions : public core::DeclaredOptions
{
    SequenceKind kind = SequenceKind::Tracking;
    std::string estimate, groundtruth, queries;

    void declare(core::OptionTable& t) override;
    /** Estimate and ground truth given and existing, queries only for localization and existing. */
    void check(const std::string& input) const;
};

struct NamedSequence
{
    std::string name;
    std::string section;  ///< "Eval.<name>"
    SequenceOptions options;
};

struct EvalConfig
{
    EvalOptions eval;
    std::vector<NamedSequence> sequences;
};

/** The section of a sequence: "Eval." + name. */
std::string sequenceSection(const std::string& name);

/** Loads and validates [Eval] and every [Eval.<name>] (see the layout above); `config_name` names the
 *  configuration in messages. */
EvalConfig loadEvalConfig(const mrpt::config::CConfigFileBase& cfg, const std::string& config_name);

}  // namespace quasiloc::eval
