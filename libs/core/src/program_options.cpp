#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/core/staged_output.h>
#include <set>
#include <sstream>

namespace quasiloc::core
{
namespace
{
std::string trim(const std::string& s)
{
    const auto b = s.find_first_not_of(" \t");
    const auto e = s.find_last_not_of(" \t");
    return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

std::string lower(std::string s)
{
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}
}  // namespace

CommandLine withOptionalConfig(CommandLine cmd)
{
    if (cmd.config_path.empty() && !cmd.flags.empty())
    {
        cmd.config_path = cmd.flags.front();
        cmd.flags.erase(cmd.flags.begin());
    }
    for (const auto& f : cmd.flags) throw InputError("command line", "unexpected argument '" + f + "'");
    return cmd;
}

CommandLine parseCommandLine(int argc, char** argv, bool config_required)
{
    CommandLine cmd;
    cmd.program = argc > 0 ? std::filesystem::path(argv[0]).filename().string() : "quasiloc";
    for (int i = 1; i < argc; ++i)
    {
        const std::string a = argv[i];
        if (a == "--set")
        {
            require(i + 1 < argc, "command line", "--set needs an argument Section.key=value");
            const std::string kv = argv[++i];
            const auto eq = kv.find('=');
            const auto dot = kv.find('.');
            require(eq != std::string::npos && dot != std::string::npos && dot > 0 && dot + 1 < eq,
                    "command line (--set " + kv + ")", "expected Section.key=value");
            cmd.overrides.emplace_back(kv.substr(0, eq), kv.substr(eq + 1));
        }
        else if (a.rfind("--set=", 0) == 0)
        {
            require(false, "command line (" + a + ")", "write --set Section.key=value (with a space)");
        }
        else if (a == "--print-timing")
            cmd.print_timing = true;
        else if (cmd.config_path.empty() && config_required && a.rfind("--", 0) != 0)
            cmd.config_path = a;
        else
            cmd.flags.push_back(a);
    }
    if (config_required) require(!cmd.config_path.empty(), "command line", "missing the INI configuration file");
    return cmd;
}

mrpt::config::CConfigFileMemory loadConfig(const CommandLine& cmd)
{
    mrpt::config::CConfigFileMemory cfg;
    if (!cmd.config_path.empty())
    {
        require(std::filesystem::is_regular_file(cmd.config_path), cmd.config_path, "configuration file not found");
        std::ifstream in(cmd.config_path);
        require(in.good(), cmd.config_path, "configuration file cannot be read");
        std::stringstream ss;
        ss << in.rdbuf();
        cfg.setContent(ss.str());
    }
    for (const auto& [section_key, value] : cmd.overrides)
    {
        const auto dot = section_key.find('.');
        cfg.write(section_key.substr(0, dot), section_key.substr(dot + 1), value);
    }
    return cfg;
}

std::vector<std::string> knownKeys(const mrpt::config::CLoadableOptions& options, const std::string& section)
{
    mrpt::config::CConfigFileMemory mem;
    options.saveToConfigFile(mem, section);
    std::vector<std::string> keys;
    mem.getAllKeys(section, keys);
    // MRPT pads key names when a value is written with a padding width or a comment.
    for (auto& k : keys) k = trim(k);
    return keys;
}

void loadOptionsChecked(mrpt::config::CLoadableOptions& options, const mrpt::config::CConfigFileBase& cfg,
                        const std::string& section, const std::string& config_name)
{
    const std::vector<std::string> known = knownKeys(options, section);
    std::set<std::string> known_lower;
    for (const auto& k : known) known_lower.insert(lower(k));
    std::vector<std::string> present;
    if (cfg.sectionExists(section)) cfg.getAllKeys(section, present);
    for (const auto& k : present)
    {
        if (known_lower.count(lower(trim(k)))) continue;
        std::string list;
        for (const auto& kk : known) list += (list.empty() ? "" : ", ") + kk;
        throw InputError(config_name + " [" + section + "] " + k,
                         "unknown key (known keys of [" + section + "]: " + list + ")");
    }
    try
    {
        options.loadFromConfigFile(cfg, section);
    }
    catch (const InputError& e)
    {
        // A value the declaration rejects ("[section] key: ...") is named with the file, as an unknown key is.
        if (e.input().rfind(config_name, 0) == 0) throw;
        throw InputError(config_name + " " + e.input(), e.problem());
    }
    catch (const std::exception& e)
    {
        throw InputError(config_name + " [" + section + "]", mrpt::exception_to_str(e));
    }
}

void requireInputFiles(const std::string& config_name, const std::string& section,
                       const std::vector<std::pair<std::string, std::string>>& key_paths, bool required)
{
    for (const auto& [key, path] : key_paths)
    {
        if (path.empty() && !required) continue;
        require(!path.empty() && std::filesystem::exists(path), config_name + ": [" + section + "] " + key,
                path.empty() ? "is required" : "'" + path + "' does not exist");
    }
}

void writeEffectiveConfig(const std::string& path, const std::vector<OptionsSection>& sections,
                          const std::string& header_comment)
{
    mrpt::config::CConfigFileMemory mem;
    for (const auto& s : sections) s.options->saveToConfigFile(mem, s.section);
    std::string content = "# " + header_comment + "\n" + mem.getContent();
    writeTextFileAtomically(path, content);
}

int runProgram(int argc, char** argv, const std::string& usage, const std::function<int(const CommandLine&)>& body,
               bool config_required)
{
    const std::string program = argc > 0 ? std::filesystem::path(argv[0]).filename().string() : "quasiloc";
    for (int i = 1; i < argc; ++i)
    {
        const std::string a = argv[i];
        if (a == "-h" || a == "--help")
        {
            std::cout << usage << std::endl;
            return 0;
        }
    }
    try
    {
        const CommandLine cmd = parseCommandLine(argc, argv, config_required);
        return body(cmd);
    }
    catch (const std::exception& e)
    {
        // Our own errors carry a complete message; anything else (MRPT, OpenCV) gets MRPT's formatting.
        const bool ours = dynamic_cast<const InputError*>(&e) != nullptr;
        std::cerr << program << ": error: " << (ours ? std::string(e.what()) : mrpt::exception_to_str(e)) << std::endl;
        if (argc < 2) std::cerr << usage << std::endl;
        return 1;
    }
}

}  // namespace quasiloc::core
