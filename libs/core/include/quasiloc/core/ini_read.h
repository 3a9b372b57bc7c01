#pragma once
// Strict INI value readers for options structs. MRPT's read_double/read_int turn "abc" into 0 and
// read_bool accepts anything; a typo in an INI value must be an error naming the key instead.
// An absent or empty key keeps the default.
#include <mrpt/config/CConfigFileBase.h>

#include <string>
#include <vector>

namespace quasiloc::core
{
/** The whole of `text` as a finite number (blanks after it allowed), else InputError(where, "'<text>' is not a finite
 *  number"): for every reader of user numbers (INI values, CSV fields), where std::stod would accept a prefix. */
double parseFiniteNumber(const std::string& text, const std::string& where);

/** "[section] key": how errors name an INI key. */
std::string iniKeyName(const std::string& section, const std::string& key);

double readIniDouble(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
                     double default_value);
int readIniInt(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
               int default_value);
/** true/false, 1/0, yes/no (case-insensitive). */
bool readIniBool(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
                 bool default_value);
/** "[a b c]" or "a b c" (blanks or commas) of finite numbers. */
std::vector<double> readIniVector(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
                                  const std::string& key, const std::vector<double>& default_value);
/** "a b c": how readIniVector's values are written back (saveToConfigFile). */
std::string iniVectorText(const std::vector<double>& v);

}  // namespace quasiloc::core
