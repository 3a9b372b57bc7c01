#include "ini_read.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <quasiloc/core/error.h>

namespace quasiloc::estimation::detail
{
std::string keyName(const std::string& section, const std::string& key) { return "[" + section + "] " + key; }

double readDouble(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
                  double def)
{
    const std::string s = cfg.read_string(section, key, "", false);
    if (s.empty()) return def;
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(s.c_str(), &end);
    while (end && (*end == ' ' || *end == '\t')) ++end;
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
    const std::string s = cfg.read_string(section, key, "", false);
    if (s.empty()) return def;
    if (s == "true" || s == "1" || s == "yes") return true;
    if (s == "false" || s == "0" || s == "no") return false;
    throw core::InputError(keyName(section, key), "'" + s + "' is not a boolean (true/false)");
}
}  // namespace quasiloc::estimation::detail
