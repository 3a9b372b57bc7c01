#include "ini_read.h"

#include <quasiloc/core/error.h>
#include <quasiloc/core/ini_read.h>

namespace quasiloc::frontend::detail
{
std::string keyName(const std::string& section, const std::string& key) { return core::iniKeyName(section, key); }

std::string readString(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
                       const std::string& def)
{
    std::string s = cfg.read_string(section, key, def, false);
    const auto b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
    return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

// The strict number and boolean readers are core's (quasiloc/core/ini_read.h); these names keep the
// front-end's options code short.
double readDouble(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
                  double def)
{
    return core::readIniDouble(cfg, section, key, def);
}

int readInt(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key, int def)
{
    return core::readIniInt(cfg, section, key, def);
}

bool readBool(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key, bool def)
{
    return core::readIniBool(cfg, section, key, def);
}

void requireKey(bool ok, const std::string& input, const std::string& section, const std::string& key,
                const std::string& problem)
{
    if (!ok) throw core::InputError(input + ": " + keyName(section, key), problem);
}
}  // namespace quasiloc::frontend::detail
