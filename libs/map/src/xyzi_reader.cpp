// "x y z i" text clouds: one point per line, blanks or commas between values, '#' comments.
#include <quasiloc/core/error.h>
#include <quasiloc/map/map_import.h>
#include <string_view>

#include "file_bytes.h"

namespace quasiloc::map
{
namespace
{
/** Splits a line into at most 8 values; returns the number of values found (or -1 for a bad token). */
int parseLine(std::string_view line, double* values, std::string& bad_token)
{
    int n = 0;
    size_t i = 0;
    while (i < line.size())
    {
        while (i < line.size() && (std::isspace(static_cast<unsigned char>(line[i])) || line[i] == ',')) ++i;
        size_t j = i;
        while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j])) && line[j] != ',') ++j;
        if (j == i) break;
        double v = 0;
        if (!detail::parseNumber(line.substr(i, j - i), v))
        {
            bad_token = std::string(line.substr(i, j - i));
            return -1;
        }
        if (n < 8) values[n] = v;
        ++n;
        i = j;
    }
    return n;
}
}  // namespace

RawCloud readXyziText(const std::string& path) { return detail::parseXyziText(detail::readFileBytes(path), path); }

RawCloud detail::parseXyziText(const std::vector<uint8_t>& bytes, const std::string& path)
{
    const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    RawCloud cloud;
    cloud.encoding = "text";
    cloud.intensity_field = "4th column";
    cloud.reserve(bytes.size() / 24);
    size_t pos = 0, line_no = 0;
    double v[8];
    std::string bad;
    while (pos < text.size())
    {
        size_t eol = text.find('\n', pos);
        if (eol == std::string_view::npos) eol = text.size();
        std::string_view line = text.substr(pos, eol - pos);
        pos = eol + 1;
        ++line_no;
        if (const auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
        const int n = parseLine(line, v, bad);
        if (n == 0) continue;
        if (n != 4)
        {
            const std::string where = "line " + std::to_string(line_no);
            if (n < 0) throw core::InputError(path, where + ": '" + bad + "' is not a number");
            if (n == 3) throw core::InputError(path, where + ": no intensity field (3 values; expected x y z i)");
            throw core::InputError(path, where + ": " + std::to_string(n) + " values (expected x y z i)");
        }
        cloud.push(static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]),
                   static_cast<float>(v[3]));
    }
    return cloud;
}

}  // namespace quasiloc::map
