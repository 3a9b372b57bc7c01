#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <quasiloc/core/error.h>
#include <quasiloc/core/ini_read.h>
#include <sstream>

namespace quasiloc::core
{
namespace
{
bool parseFiniteDouble(const std::string& s, double& v)
{
    char* end = nullptr;
    errno = 0;
    v = std::strtod(s.c_str(), &end);
    while (end && (*end == ' ' || *end == '\t')) ++end;
    return errno == 0 && end != s.c_str() && *end == '\0' && std::isfinite(v);
}
}  // namespace

double parseFiniteNumber(const std::string& text, const std::string& where)
{
    double v = 0;
    require(parseFiniteDouble(text, v), where, "'" + text + "' is not a finite number");
    return v;
}

std::string iniKeyName(const std::string& section, const std::string& key) { return "[" + section + "] " + key; }

double readIniDouble(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
                     double default_value)
{
    const std::string s = cfg.read_string(section, key, "", false);
    if (s.empty()) return default_value;
    return parseFiniteNumber(s, iniKeyName(section, key));
}

int readIniInt(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
               int default_value)
{
    const double v = readIniDouble(cfg, section, key, default_value);
    require(v == std::floor(v) && std::abs(v) <= 1e9, iniKeyName(section, key),
            std::to_string(v) + " is not an integer");
    return static_cast<int>(v);
}

bool readIniBool(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
                 bool default_value)
{
    std::string s = cfg.read_string(section, key, "", false);
    if (s.empty()) return default_value;
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    if (s == "true" || s == "1" || s == "yes") return true;
    if (s == "false" || s == "0" || s == "no") return false;
    throw InputError(iniKeyName(section, key), "'" + s + "' is not a boolean (true/false)");
}

std::vector<double> readIniVector(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
                                  const std::string& key, const std::vector<double>& default_value)
{
    std::string s = cfg.read_string(section, key, "", false);
    if (s.empty()) return default_value;
    std::replace_if(
        s.begin(), s.end(), [](char c) { return c == '[' || c == ']' || c == ',' || c == ';'; }, ' ');
    std::istringstream in(s);
    std::vector<double> out;
    std::string token;
    while (in >> token)
    {
        double v = 0;
        require(parseFiniteDouble(token, v), iniKeyName(section, key), "'" + token + "' is not a finite number");
        out.push_back(v);
    }
    return out;
}

std::string iniVectorText(const std::vector<double>& v)
{
    std::ostringstream s;
    for (size_t i = 0; i < v.size(); ++i) s << (i ? " " : "") << v[i];
    return s.str();
}

}  // namespace quasiloc::core
