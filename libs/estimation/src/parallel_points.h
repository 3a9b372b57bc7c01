#pragma once
// Per-point loops of the window's big residual blocks, split over the thread pool.
#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <cstddef>

namespace quasiloc::estimation::detail
{
/** Calls body(begin, end) over [0, n) in a few stripes on cv::parallel_for_'s pool (one call when n is small).
 *  For loops whose iterations write their own outputs only (a residual and its Jacobian row): the result is the
 *  same bit for bit whoever runs which stripe. The window runs after the frame's other tasks, when the second
 *  core is free, and Ceres evaluates one residual block on one thread. */
template <class Body>
void forPointStripes(size_t n, const Body& body)
{
    constexpr size_t kMinPerStripe = 256;
    const int stripes = int(std::min<size_t>(4, n / kMinPerStripe));
    if (stripes < 2)
    {
        body(size_t(0), n);
        return;
    }
    cv::parallel_for_(
        cv::Range(0, stripes),
        [&](const cv::Range& r) {
            for (int s = r.start; s < r.end; ++s) body(n * size_t(s) / size_t(stripes), n * size_t(s + 1) / size_t(stripes));
        },
        stripes);
}
}  // namespace quasiloc::estimation::detail
