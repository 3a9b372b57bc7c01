#pragma once
// Strict INI value reading shared by the front-end's options structs: MRPT's read_double/read_int turn "abc"
// into 0, but a typo in an INI value must be an error naming the key.
#include <mrpt/config/CConfigFileBase.h>

#include <string>

namespace quasiloc::frontend::detail
{
std::string keyName(const std::string& section, const std::string& key);
double readDouble(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
                  double def);
int readInt(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key, int def);
bool readBool(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key, bool def);
std::string readString(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
                       const std::string& def);
/** InputError "<input>: [<section>] <key>: <problem>" unless `ok`. */
void requireKey(bool ok, const std::string& input, const std::string& section, const std::string& key,
                const std::string& problem);
}  // namespace quasiloc::frontend::detail
