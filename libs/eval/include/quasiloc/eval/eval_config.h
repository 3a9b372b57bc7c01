#pragma once
// Configuration of quasiloc-eval. INI layout (paths relative to the working directory; example with
// every key documented: share/quasiloc/eval_example.ini). Put comments on their own lines: MRPT's INI
// reader keeps a "; ..." after a value as part of the value.
//
//   [Eval]
//   output_dir = out/eval
//   max_dt_s = 0.02
//   align = none
//   rpe_delta_s = 1.0
//   rpe_delta_frames = 0
//   recall_thresholds_m = [0.1 0.3 1.0]
//   recall_thresholds_deg = []
//   sequence_names = [v101 v101_loc]
//
//   [Eval.v101]
//   kind = tracking
//   estimate = out/v101.tum
//   groundtruth = ../shared/data/euroc/groundtruth/cam0/V1_01_easy.txt
//
//   [Eval.v101_loc]
//   kind = localization
//   estimate = out/v101_loc.tum
//   groundtruth = ../shared/data/euroc/groundtruth/cam0/V1_01_easy.txt
//   queries = out/v101_loc_queries.txt
//
// [Eval]: output_dir receives report.md, report.json, eval_effective.ini, <sequence>_errors.csv;
// max_dt_s bounds |t_est - t_gt| of an associated pair; align = none | se3 | sim3 adds an aligned ATE (the
// unaligned one is always first); the RPE step is rpe_delta_s seconds, or rpe_delta_frames associated poses
// when rpe_delta_s = 0 (exactly one must be > 0); recall_thresholds_deg is empty (translation only) or has
// one value per recall_thresholds_m entry; every name in sequence_names has a section [Eval.<name>].
// [Eval.<name>]: kind = tracking | localization; estimate and groundtruth are TUM files of T_map_cam;
// queries (localization only, optional) lists every queried timestamp (see readQueryTimestamps).
//
// The command line splits "--set Section.key=value" at the first dot, so "--set Eval.v101.estimate=x.tum"
// arrives as key "v101.estimate" of [Eval]; the loader moves such keys into [Eval.v101].
// Unknown keys, an [Eval.*] section not listed in sequence_names, a listed name without its section, and
// missing files are errors. Other sections are ignored (the INI may serve other programs too).
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CLoadableOptions.h>

#include <quasiloc/eval/localization_metrics.h>
#include <quasiloc/eval/trajectory_metrics.h>
#include <string>
#include <vector>

namespace quasiloc::eval
{
struct EvalOptions : public mrpt::config::CLoadableOptions
{
    std::string output_dir = "out/eval";
    double max_dt_s = 0.02;
    std::string align = "none";
    double rpe_delta_s = 1.0;
    int rpe_delta_frames = 0;
    std::vector<double> recall_thresholds_m = {0.1, 0.3, 1.0};
    std::vector<double> recall_thresholds_deg;  ///< empty: translation-only recall
    std::vector<std::string> sequence_names;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
    /** InputError naming `input` and the key for a bad value. */
    void check(const std::string& input) const;

    Alignment alignment() const { return alignmentFromString(align, "align"); }
    RpeDelta rpeDelta() const { return {rpe_delta_s, rpe_delta_frames}; }
    std::vector<RecallThreshold> recallThresholds() const;
};

enum class SequenceKind
{
    Tracking,
    Localization
};

struct SequenceOptions : public mrpt::config::CLoadableOptions
{
    std::string kind = "tracking";
    std::string estimate, groundtruth, queries;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
    /** Kind valid, estimate and ground truth given and existing, queries only for localization and existing. */
    void check(const std::string& input) const;
    SequenceKind sequenceKind() const;
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

/** "[a b c]", "a, b", "a b" -> {a, b, c}; brackets optional, separators spaces, tabs or commas. */
std::vector<std::string> parseList(const std::string& text);

}  // namespace quasiloc::eval
