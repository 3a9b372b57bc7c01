#pragma once
// Strict INI value readers: MRPT's read_double turns "abc" into 0; a typo must be an error instead.
#include <mrpt/config/CConfigFileBase.h>

#include <string>

namespace quasiloc::estimation::detail
{
double readDouble(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
                  double def);
int readInt(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key, int def);
bool readBool(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key, bool def);
std::string keyName(const std::string& section, const std::string& key);
}  // namespace quasiloc::estimation::detail
