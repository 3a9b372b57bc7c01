#include "euroc_csv.h"

#include <filesystem>
#include <fstream>
#include <quasiloc/core/error.h>
#include <sstream>

namespace quasiloc::dataset::csv
{
namespace
{
std::string trim(const std::string& s)
{
    const auto b = s.find_first_not_of(" \t\r");
    if (b == std::string::npos) return "";
    const auto e = s.find_last_not_of(" \t\r");
    return s.substr(b, e - b + 1);
}
}  // namespace

std::vector<Line> readLines(const std::string& path)
{
    core::require(std::filesystem::is_regular_file(path), path, "csv file not found");
    std::ifstream in(path);
    core::require(in.good(), path, "csv file unreadable");
    std::vector<Line> rows;
    std::string line;
    int line_no = 0;
    while (std::getline(in, line))
    {
        ++line_no;
        const std::string t = trim(line);
        if (t.empty() || t[0] == '#') continue;
        Line row{line_no, {}};
        std::stringstream ss(t);
        std::string f;
        while (std::getline(ss, f, ',')) row.fields.push_back(trim(f));
        rows.push_back(std::move(row));
    }
    return rows;
}

std::string where(const std::string& path, const Line& line) { return path + ":" + std::to_string(line.line_no); }

std::int64_t parseTimestampNs(const std::string& s, const std::string& where)
{
    core::require(!s.empty() && s.find_first_not_of("0123456789") == std::string::npos, where,
                  "timestamp '" + s + "' is not an integer number of nanoseconds");
    try
    {
        return std::stoll(s);
    }
    catch (const std::exception&)
    {
        throw core::InputError(where, "timestamp '" + s + "' out of range");
    }
}

}  // namespace quasiloc::dataset::csv
