#pragma once
// Summary statistics of a list of non-negative errors (metres or degrees), as the TUM/evo tools report
// them: RMSE, mean, median, max, min and the population standard deviation (numpy.std).
#include <cstddef>
#include <vector>

namespace quasiloc::eval
{
struct ErrorStats
{
    size_t count = 0;
    // All NaN when count == 0 (reports print "-" / JSON null).
    double rmse, mean, median, max, min, std;
    ErrorStats();
};

/** Statistics of `values`; the median of an even count is the mean of the two middle values. */
ErrorStats computeStats(std::vector<double> values);

}  // namespace quasiloc::eval
