#include "rank_stats.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <numeric>
#include <sstream>

namespace quasiloc::bench
{
std::vector<double> ranks(const std::vector<double>& v)
{
    std::vector<size_t> order(v.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return v[a] < v[b]; });
    std::vector<double> r(v.size());
    for (size_t i = 0; i < order.size();)
    {
        size_t j = i + 1;
        while (j < order.size() && v[order[j]] == v[order[i]]) ++j;
        const double mean_rank = 0.5 * double(i + j + 1);  // ranks i+1 .. j
        for (size_t k = i; k < j; ++k) r[order[k]] = mean_rank;
        i = j;
    }
    return r;
}

double pearson(const std::vector<double>& a, const std::vector<double>& b)
{
    const size_t n = std::min(a.size(), b.size());
    if (n < 2) return NAN;
    double ma = 0, mb = 0;
    for (size_t i = 0; i < n; ++i) ma += a[i], mb += b[i];
    ma /= double(n), mb /= double(n);
    double sab = 0, saa = 0, sbb = 0;
    for (size_t i = 0; i < n; ++i)
    {
        const double da = a[i] - ma, db = b[i] - mb;
        sab += da * db, saa += da * da, sbb += db * db;
    }
    if (saa <= 0 || sbb <= 0) return NAN;
    return sab / std::sqrt(saa * sbb);
}

double spearman(const std::vector<double>& a, const std::vector<double>& b, size_t min_n)
{
    if (a.size() != b.size() || a.size() < std::max<size_t>(min_n, 2)) return NAN;
    return pearson(ranks(a), ranks(b));
}

Summary summarise(const std::vector<double>& v)
{
    std::vector<double> f;
    for (double x : v)
        if (std::isfinite(x)) f.push_back(x);
    Summary s;
    s.n = f.size();
    if (f.empty()) return s;
    std::sort(f.begin(), f.end());
    const auto quantile = [&](double q) {
        const double pos = q * double(f.size() - 1);
        const size_t lo = size_t(std::floor(pos)), hi = std::min(f.size() - 1, lo + 1);
        return f[lo] + (pos - double(lo)) * (f[hi] - f[lo]);
    };
    s.median = quantile(0.5), s.q25 = quantile(0.25), s.q75 = quantile(0.75);
    return s;
}

std::string formatSummary(const Summary& s, int precision)
{
    if (s.n == 0) return "-";
    std::ostringstream o;
    o << std::fixed << std::setprecision(precision) << s.median << " [" << s.q25 << ", " << s.q75 << "]";
    return o.str();
}

}  // namespace quasiloc::bench
