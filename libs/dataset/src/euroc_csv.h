#pragma once
// Private to libs/dataset: the strict line and field parsing shared by the EuRoC csv readers (euroc.cpp,
// euroc_imu_csv.cpp). Errors are InputErrors naming "<file>:<line>".
#include <cstdint>
#include <string>
#include <vector>

namespace quasiloc::dataset::csv
{
struct Line
{
    int line_no = 0;
    std::vector<std::string> fields;  ///< trimmed
};

/** Data lines of a csv file (comments '#' and blank lines skipped); InputError when missing or unreadable. */
std::vector<Line> readLines(const std::string& path);

/** "<path>:<line_no>", the `where` of a line's errors. */
std::string where(const std::string& path, const Line& line);

/** A non-negative integer number of nanoseconds. */
std::int64_t parseTimestampNs(const std::string& s, const std::string& where);

}  // namespace quasiloc::dataset::csv
