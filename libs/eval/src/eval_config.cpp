#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/eval/eval_config.h>
#include <set>

namespace quasiloc::eval
{
namespace
{
const std::string kSequencePrefix = "Eval.";

bool validName(const std::string& n)
{
    return !n.empty() &&
           std::all_of(n.begin(), n.end(), [](unsigned char c) { return std::isalnum(c) || c == '_' || c == '-'; });
}
}  // namespace

void EvalOptions::declare(core::OptionTable& t)
{
    using core::Range;
    t.add("output_dir", output_dir, "receives report.md, report.json, eval_effective.ini, <sequence>_errors.csv");
    t.add("max_dt_s", max_dt_s, "s", Range::atLeast(0), "an associated pair has |t_est - t_gt| <= this");
    t.addEnum("association", association,
              {{"nearest", GroundTruthLookup::Nearest}, {"interpolated", GroundTruthLookup::Interpolated}},
              "nearest: the ground-truth pose nearest in time, one-to-one (TUM, evo); interpolated: the ground truth "
              "interpolated at the estimate's time when the nearer sample is within max_dt_s (as quasiloc-track)");
    t.addEnum("align", align, alignmentNames(),
              "the estimate the RPE is computed on: none and se3 (the same RPE), sim3 (scale corrected, monocular); "
              "the ATE is reported unaligned, SE(3)- and Sim(3)-aligned whatever this is");
    t.add("rpe_delta_m", rpe_delta_m, "m", Range::atLeast(0),
          "RPE per this much path of the estimate, consecutive pairs as evo_rpe --delta_unit m (0: none)");
    t.add("rpe_delta_s", rpe_delta_s, "s", Range::atLeast(0),
          "RPE per this many seconds, every pose, as TUM evaluate_rpe.py --fixed_delta --delta_unit s (0: none)");
    t.add("rpe_delta_frames", rpe_delta_frames, "", Range::atLeast(0),
          "RPE per this many associated poses, every pose (0: none)");
    t.add("recall_thresholds_m", recall_thresholds_m, "m", Range::above(0), "localization recall thresholds");
    t.add("recall_thresholds_deg", recall_thresholds_deg, "deg", Range::above(0),
          "empty (translation only) or one per recall_thresholds_m entry");
    t.add("sequence_names", sequence_names, "one section [Eval.<name>] per name");
}

void EvalOptions::check(const std::string& input) const
{
    checkRanges(input, "Eval");
    const std::string in = input + " [Eval] ";
    core::require(!output_dir.empty(), in + "output_dir", "is empty");
    core::require(rpe_delta_m > 0 || rpe_delta_s > 0 || rpe_delta_frames > 0,
                  in + "rpe_delta_m / rpe_delta_s / rpe_delta_frames", "at least one must be > 0");
    core::require(!recall_thresholds_m.empty(), in + "recall_thresholds_m", "needs at least one threshold");
    core::require(recall_thresholds_deg.empty() || recall_thresholds_deg.size() == recall_thresholds_m.size(),
                  in + "recall_thresholds_deg", "must be empty or have one value per recall_thresholds_m entry");
    core::require(!sequence_names.empty(), in + "sequence_names", "lists no sequence");
    std::set<std::string> seen;
    for (const auto& n : sequence_names)
    {
        core::require(validName(n), in + "sequence_names",
                      "'" + n + "' is not a valid name (letters, digits, '_' and '-' only)");
        core::require(seen.insert(n).second, in + "sequence_names", "'" + n + "' is listed twice");
    }
}

std::vector<RpeDelta> EvalOptions::rpeDeltas() const
{
    std::vector<RpeDelta> out;
    if (rpe_delta_m > 0) out.push_back({rpe_delta_m, RpeUnit::Metres});
    if (rpe_delta_s > 0) out.push_back({rpe_delta_s, RpeUnit::Seconds});
    if (rpe_delta_frames > 0) out.push_back({double(rpe_delta_frames), RpeUnit::Frames});
    return out;
}

std::vector<RecallThreshold> EvalOptions::recallThresholds() const
{
    std::vector<RecallThreshold> out;
    for (size_t i = 0; i < recall_thresholds_m.size(); ++i)
    {
        RecallThreshold t;
        t.trans_m = recall_thresholds_m[i];
        if (!recall_thresholds_deg.empty()) t.rot_deg = recall_thresholds_deg[i];
        out.push_back(t);
    }
    return out;
}

namespace
{
const std::vector<std::pair<std::string, SequenceKind>> kSequenceKinds = {{"tracking", SequenceKind::Tracking},
                                                                          {"localization", SequenceKind::Localization}};
}  // namespace

std::string toString(SequenceKind k)
{
    for (const auto& [name, value] : kSequenceKinds)
        if (value == k) return name;
    return "?";
}

void SequenceOptions::declare(core::OptionTable& t)
{
    t.addEnum("kind", kind, kSequenceKinds, "tracking: a trajectory (ATE, RPE); localization: localized queries");
    t.add("estimate", estimate, "TUM file of T_map_cam");
    t.add("groundtruth", groundtruth, "TUM file of T_map_cam");
    t.add("queries", queries, "localization only, optional: every queried timestamp (unlocalized ones count)");
}

void SequenceOptions::check(const std::string& input) const
{
    const auto requireFile = [&](const std::string& key, const std::string& path) {
        core::require(!path.empty(), input + " " + key, "is required");
        core::require(std::filesystem::is_regular_file(path), input + " " + key + " = " + path, "file not found");
    };
    requireFile("estimate", estimate);
    requireFile("groundtruth", groundtruth);
    if (!queries.empty())
    {
        core::require(kind == SequenceKind::Localization, input + " queries",
                      "only a localization sequence takes a query list");
        requireFile("queries", queries);
    }
}

std::string sequenceSection(const std::string& name) { return kSequencePrefix + name; }

namespace
{
/** A copy of `cfg` in which every "[Eval] <name>.<key>" (what "--set Eval.<name>.<key>=v" produces, since
 *  the command line splits at the first dot) is moved to "[Eval.<name>] <key>". */
mrpt::config::CConfigFileMemory foldDottedOverrides(const mrpt::config::CConfigFileBase& cfg)
{
    mrpt::config::CConfigFileMemory out;
    std::vector<std::string> sections;
    cfg.getAllSections(sections);
    std::vector<std::array<std::string, 3>> dotted;  // applied last: an override wins over the file
    for (const auto& sec : sections)
    {
        std::vector<std::string> keys;
        cfg.getAllKeys(sec, keys);
        for (const auto& k : keys)
        {
            const std::string v = cfg.read_string(sec, k, "");
            const auto dot = k.find('.');
            if (sec == "Eval" && dot != std::string::npos && dot > 0)
                dotted.push_back({kSequencePrefix + k.substr(0, dot), k.substr(dot + 1), v});
            else
                out.write(sec, k, v);
        }
    }
    for (const auto& [sec, k, v] : dotted) out.write(sec, k, v);
    return out;
}
}  // namespace

EvalConfig loadEvalConfig(const mrpt::config::CConfigFileBase& cfg_in, const std::string& config_name)
{
    const mrpt::config::CConfigFileMemory cfg = foldDottedOverrides(cfg_in);
    EvalConfig out;
    core::require(cfg.sectionExists("Eval"), config_name, "section [Eval] is missing");
    core::loadOptionsChecked(out.eval, cfg, "Eval", config_name);
    out.eval.check(config_name);
    for (const auto& name : out.eval.sequence_names)
    {
        NamedSequence s;
        s.name = name;
        s.section = sequenceSection(name);
        core::require(cfg.sectionExists(s.section), config_name + " [" + s.section + "]",
                      "section is missing (sequence '" + name + "' is listed in [Eval] sequence_names)");
        core::loadOptionsChecked(s.options, cfg, s.section, config_name);
        s.options.check(config_name + " [" + s.section + "]");
        out.sequences.push_back(s);
    }
    // A sequence section nobody lists is most likely a typo in sequence_names: refuse rather than skip it.
    std::vector<std::string> sections;
    cfg.getAllSections(sections);
    const std::set<std::string> listed(out.eval.sequence_names.begin(), out.eval.sequence_names.end());
    for (const auto& sec : sections)
        if (sec.rfind(kSequencePrefix, 0) == 0)
            core::require(listed.count(sec.substr(kSequencePrefix.size())) > 0, config_name + " [" + sec + "]",
                          "section is not listed in [Eval] sequence_names");
    return out;
}

}  // namespace quasiloc::eval
