#pragma once
// The command line shared by every quasiloc program:
//     <program> <config.ini> [--set Section.key=value]... [--print-timing]
// plus per-program plain flags where a program allows them. The INI file and the --set overrides are
// merged into one in-memory configuration; each options struct loads its section from it, unknown
// keys in a program's sections are rejected, and the effective configuration is written beside the
// program's outputs.
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/config/CLoadableOptions.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace quasiloc::core
{
struct CommandLine
{
    std::string program;
    std::string config_path;  ///< empty when the program was run with plain flags only
    std::vector<std::pair<std::string, std::string>> overrides;  ///< ("Section.key", "value")
    std::vector<std::string> flags;                              ///< everything else, in order (program-specific)
    bool print_timing = false;
};

/** Parses argv. If `config_required`, the first positional argument must be an INI file. */
CommandLine parseCommandLine(int argc, char** argv, bool config_required = true);

/** For a program whose INI file is optional: the first plain argument, if any, is the INI file; any further plain
 *  argument is an InputError. */
CommandLine withOptionalConfig(CommandLine cmd);

/** Reads the INI file (InputError if missing or unreadable) and applies the overrides.
 *  A malformed override ("--set foo", "--set .k=v") is an InputError. */
mrpt::config::CConfigFileMemory loadConfig(const CommandLine& cmd);

/** Every key that `options` writes with saveToConfigFile() is a known key of `section`. */
std::vector<std::string> knownKeys(const mrpt::config::CLoadableOptions& options, const std::string& section);

/** Loads `options` from `section` after checking that the section has no unknown key (InputError
 *  naming the key, the section, the file, and the known keys). A value the options reject is an InputError
 *  that names the file too ("<config_name> [section] key: ..."). */
void loadOptionsChecked(mrpt::config::CLoadableOptions& options, const mrpt::config::CConfigFileBase& cfg,
                        const std::string& section, const std::string& config_name);

/** Input files named by INI keys: InputError "<config_name>: [section] key" with "is required" for an empty value
 *  (when `required`) or "'<path>' does not exist" for a missing file. Empty optional values pass. */
void requireInputFiles(const std::string& config_name, const std::string& section,
                       const std::vector<std::pair<std::string, std::string>>& key_paths, bool required = true);

/** One named section of a program's configuration. */
struct OptionsSection
{
    std::string section;
    const mrpt::config::CLoadableOptions* options;
};

/** Writes every section's effective values (after defaults and overrides) to an INI file, atomically. */
void writeEffectiveConfig(const std::string& path, const std::vector<OptionsSection>& sections,
                          const std::string& header_comment);

/** Runs a program body, turning any exception into "<program>: error: <message>" on stderr and exit
 *  code 1. Use from main(): `return quasiloc::core::runProgram(argc, argv, usage, body);` */
int runProgram(int argc, char** argv, const std::string& usage, const std::function<int(const CommandLine&)>& body,
               bool config_required = true);

}  // namespace quasiloc::core
