#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/eval/eval_config.h>
#include <set>
#include <stdexcept>

namespace quasiloc::eval
{
namespace
{
const std::string kSequencePrefix = "Eval.";

std::string trim(const std::string& s)
{
    const auto a = s.find_first_not_of(" \t\r\n");
    if (a == std::string::npos) return "";
    const auto b = s.find_last_not_of(" \t\r\n");
    return s.substr(a, b - a + 1);
}

// MRPT's read_double/read_int accept "abc" as 0; these reject anything that is not entirely a number.
// They throw std::runtime_error; loadOptionsChecked adds the file and section to the message.
double parseDouble(const std::string& text, const std::string& key)
{
    const std::string t = trim(text);
    size_t used = 0;
    double v = 0;
    try
    {
        v = std::stod(t, &used);
    }
    catch (const std::exception&)
    {
        used = 0;
    }
    if (t.empty() || used != t.size()) throw std::runtime_error(key + ": not a number: '" + text + "'");
    return v;
}

double readDouble(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
                  double def)
{
    const std::string s = cfg.read_string(section, key, "");
    return trim(s).empty() ? def : parseDouble(s, key);
}

int readInt(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key, int def)
{
    const double v = readDouble(cfg, section, key, def);
    if (v != std::floor(v) || std::abs(v) > 1e9) throw std::runtime_error(key + ": not an integer");
    return static_cast<int>(v);
}

std::vector<double> readDoubles(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
                                const std::string& key, const std::vector<double>& def)
{
    if (!cfg.keyExists(section, key)) return def;
    std::vector<double> out;
    for (const auto& tok : parseList(cfg.read_string(section, key, ""))) out.push_back(parseDouble(tok, key));
    return out;
}

template <typename T>
std::string listToString(const std::vector<T>& v)
{
    std::string s = "[";
    for (size_t i = 0; i < v.size(); ++i)
    {
        if constexpr (std::is_same_v<T, double>)
        {
            char buf[32];
            std::snprintf(buf, sizeof(buf), "%.10g", v[i]);
            s += (i ? " " : "") + std::string(buf);
        }
        else
            s += (i ? " " : "") + v[i];
    }
    return s + "]";
}

bool validName(const std::string& n)
{
    return !n.empty() && std::all_of(n.begin(), n.end(), [](unsigned char c) {
        return std::isalnum(c) || c == '_' || c == '-';
    });
}
}  // namespace

std::vector<std::string> parseList(const std::string& text)
{
    std::string t = trim(text);
    if (!t.empty() && t.front() == '[') t.erase(0, 1);
    if (!t.empty() && t.back() == ']') t.pop_back();
    std::replace(t.begin(), t.end(), ',', ' ');
    std::replace(t.begin(), t.end(), '\t', ' ');
    std::vector<std::string> out;
    size_t pos = 0;
    while (pos < t.size())
    {
        const auto a = t.find_first_not_of(' ', pos);
        if (a == std::string::npos) break;
        const auto b = t.find(' ', a);
        out.push_back(t.substr(a, b == std::string::npos ? std::string::npos : b - a));
        pos = b == std::string::npos ? t.size() : b;
    }
    return out;
}

void EvalOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    output_dir = trim(cfg.read_string(section, "output_dir", output_dir));
    max_dt_s = readDouble(cfg, section, "max_dt_s", max_dt_s);
    align = trim(cfg.read_string(section, "align", align));
    rpe_delta_s = readDouble(cfg, section, "rpe_delta_s", rpe_delta_s);
    rpe_delta_frames = readInt(cfg, section, "rpe_delta_frames", rpe_delta_frames);
    recall_thresholds_m = readDoubles(cfg, section, "recall_thresholds_m", recall_thresholds_m);
    recall_thresholds_deg = readDoubles(cfg, section, "recall_thresholds_deg", recall_thresholds_deg);
    if (cfg.keyExists(section, "sequence_names")) sequence_names = parseList(cfg.read_string(section, "sequence_names", ""));
}

void EvalOptions::saveToConfigFile(mrpt::config::CConfigFileBase& cfg, const std::string& section) const
{
    char buf[32];
    cfg.write(section, "output_dir", output_dir);
    std::snprintf(buf, sizeof(buf), "%.10g", max_dt_s);
    cfg.write(section, "max_dt_s", std::string(buf));
    cfg.write(section, "align", align);
    std::snprintf(buf, sizeof(buf), "%.10g", rpe_delta_s);
    cfg.write(section, "rpe_delta_s", std::string(buf));
    cfg.write(section, "rpe_delta_frames", rpe_delta_frames);
    cfg.write(section, "recall_thresholds_m", listToString(recall_thresholds_m));
    cfg.write(section, "recall_thresholds_deg", listToString(recall_thresholds_deg));
    cfg.write(section, "sequence_names", listToString(sequence_names));
}

void EvalOptions::check(const std::string& input) const
{
    const std::string in = input + " [Eval] ";
    core::require(!output_dir.empty(), in + "output_dir", "is empty");
    core::require(std::isfinite(max_dt_s) && max_dt_s >= 0, in + "max_dt_s", "must be >= 0");
    alignmentFromString(align, in + "align");
    core::require(std::isfinite(rpe_delta_s) && rpe_delta_s >= 0, in + "rpe_delta_s", "must be >= 0");
    core::require(rpe_delta_frames >= 0, in + "rpe_delta_frames", "must be >= 0");
    core::require((rpe_delta_s > 0) != (rpe_delta_frames > 0), in + "rpe_delta_s / rpe_delta_frames",
                  "exactly one must be > 0 (to use rpe_delta_frames, set rpe_delta_s = 0)");
    core::require(!recall_thresholds_m.empty(), in + "recall_thresholds_m", "needs at least one threshold");
    for (double v : recall_thresholds_m)
        core::require(std::isfinite(v) && v > 0, in + "recall_thresholds_m", "thresholds must be > 0");
    core::require(recall_thresholds_deg.empty() || recall_thresholds_deg.size() == recall_thresholds_m.size(),
                  in + "recall_thresholds_deg", "must be empty or have one value per recall_thresholds_m entry");
    for (double v : recall_thresholds_deg)
        core::require(std::isfinite(v) && v > 0, in + "recall_thresholds_deg", "thresholds must be > 0");
    core::require(!sequence_names.empty(), in + "sequence_names", "lists no sequence");
    std::set<std::string> seen;
    for (const auto& n : sequence_names)
    {
        core::require(validName(n), in + "sequence_names",
                      "'" + n + "' is not a valid name (letters, digits, '_' and '-' only)");
        core::require(seen.insert(n).second, in + "sequence_names", "'" + n + "' is listed twice");
    }
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

void SequenceOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    kind = trim(cfg.read_string(section, "kind", kind));
    estimate = trim(cfg.read_string(section, "estimate", estimate));
    groundtruth = trim(cfg.read_string(section, "groundtruth", groundtruth));
    queries = trim(cfg.read_string(section, "queries", queries));
}

void SequenceOptions::saveToConfigFile(mrpt::config::CConfigFileBase& cfg, const std::string& section) const
{
    cfg.write(section, "kind", kind);
    cfg.write(section, "estimate", estimate);
    cfg.write(section, "groundtruth", groundtruth);
    cfg.write(section, "queries", queries);
}

SequenceKind SequenceOptions::sequenceKind() const
{
    if (kind == "tracking") return SequenceKind::Tracking;
    if (kind == "localization") return SequenceKind::Localization;
    throw core::InputError("kind", "unknown sequence kind '" + kind + "' (expected tracking or localization)");
}

void SequenceOptions::check(const std::string& input) const
{
    core::require(kind == "tracking" || kind == "localization", input + " kind",
                  "unknown sequence kind '" + kind + "' (expected tracking or localization)");
    const auto requireFile = [&](const std::string& key, const std::string& path) {
        core::require(!path.empty(), input + " " + key, "is required");
        core::require(std::filesystem::is_regular_file(path), input + " " + key + " = " + path, "file not found");
    };
    requireFile("estimate", estimate);
    requireFile("groundtruth", groundtruth);
    if (!queries.empty())
    {
        core::require(kind == "localization", input + " queries", "only a localization sequence takes a query list");
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
