#pragma once
// Small statistics for the cross-modal tables: Spearman's rank correlation and per-frame summaries.
#include <cstdint>
#include <string>
#include <vector>

namespace quasiloc::bench
{
/** Ranks 1..n of v, ties sharing their mean rank. */
std::vector<double> ranks(const std::vector<double>& v);

/** Spearman's rank correlation of a and b (same length); NaN when fewer than min_n pairs or either is constant. */
double spearman(const std::vector<double>& a, const std::vector<double>& b, size_t min_n = 30);

/** Pearson correlation; NaN when fewer than 2 pairs or either is constant. */
double pearson(const std::vector<double>& a, const std::vector<double>& b);

/** Median and inter-quartile range of the finite values of v (NaN values are skipped). */
struct Summary
{
    double median = 0, q25 = 0, q75 = 0;
    size_t n = 0;  ///< finite values summarised
};
Summary summarise(const std::vector<double>& v);

/** "0.123 [0.101, 0.145]" with `precision` decimals, "-" when nothing was summarised. */
std::string formatSummary(const Summary& s, int precision = 3);

}  // namespace quasiloc::bench
