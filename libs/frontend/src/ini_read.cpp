#include "ini_read.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <quasiloc/core/error.h>

namespace quasiloc::frontend::detail
{
std::string keyName(const std::string& section, const std::string& key) { return "[" + section + "] " + key; }

std::string readString(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
                       const std::string& def)
{
    std::string s = cfg.read_string(section, key, def, false);
    const auto b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
    return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

double readDouble(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
                  double def)
{
    const std::string s = readString(cfg, section, key, "");
    if (s.empty()) return def;
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(s.c_str(), &end);
    if (errno != 0 || end == s.c_str() || *end != '\0' || !std::isfinite(v))
        throw core::InputError(keyName(section, key), "'" + s + "' is not a finite number");
    return v;
}

int readInt(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key, int def)
{
    const double v = readDouble(cfg, section, key, def);
    if (v != std::floor(v) || std::abs(v) > 1e9)
        throw core::InputError(keyName(section, key), std::to_string(v) + " is not an integer");
    return static_cast<int>(v);
}

bool readBool(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key, bool def)
{
    std::string s = readString(cfg, section, key, "");
    if (s.empty()) return def;
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (s == "true" || s == "1" || s == "yes") return true;
    if (s == "false" || s == "0" || s == "no") return false;
    throw core::InputError(keyName(section, key), "'" + s + "' is not a boolean (true/false)");
}

void requireKey(bool ok, const std::string& input, const std::string& section, const std::string& key,
                const std::string& problem)
{
    if (!ok) throw core::InputError(input + ": " + keyName(section, key), problem);
}
}  // namespace quasiloc::frontend::detail
