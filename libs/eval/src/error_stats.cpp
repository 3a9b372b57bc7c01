#include <algorithm>
#include <cmath>
#include <limits>
#include <quasiloc/eval/error_stats.h>

namespace quasiloc::eval
{
ErrorStats::ErrorStats() { rmse = mean = median = max = min = std = std::numeric_limits<double>::quiet_NaN(); }

ErrorStats computeStats(std::vector<double> values)
{
    ErrorStats s;
    s.count = values.size();
    if (values.empty()) return s;
    const double n = static_cast<double>(values.size());
    double sum = 0, sum_sq = 0;
    for (double v : values)
    {
        sum += v;
        sum_sq += v * v;
    }
    s.mean = sum / n;
    s.rmse = std::sqrt(sum_sq / n);
    // Two-pass variance: the one-pass formula loses precision when errors are nearly equal.
    double var = 0;
    for (double v : values) var += (v - s.mean) * (v - s.mean);
    s.std = std::sqrt(var / n);
    std::sort(values.begin(), values.end());
    s.min = values.front();
    s.max = values.back();
    const size_t mid = values.size() / 2;
    s.median = values.size() % 2 ? values[mid] : 0.5 * (values[mid - 1] + values[mid]);
    return s;
}

}  // namespace quasiloc::eval
