#pragma once
// Per-point loops of the window's big residual blocks and the direct alignment's sums, split over the thread pool.
#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <array>
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
            for (int s = r.start; s < r.end; ++s)
                body(n * size_t(s) / size_t(stripes), n * size_t(s + 1) / size_t(stripes));
        },
        stripes);
}

/** The sum of body(begin, end, part) over [0, n) in kStripes fixed stripes, each summed in order and then added in
 *  stripe order: the same bits whichever thread runs which stripe, and whether the pool runs them at all.
 * forPointStripes' twin for sums (the direct alignment's cost and normal equations): each stripe adds into its own
 * part. The LM runs on the tracking thread while the worker has often finished its tasks: the second core takes
 * stripes. */
constexpr int kStripes = 4;
template <class Part, class Body>
Part sumInStripes(size_t n, const Part& zero, const Body& body)
{
    std::array<Part, kStripes> parts;
    parts.fill(zero);
    const auto run = [&](int s) { body(n * size_t(s) / kStripes, n * size_t(s + 1) / kStripes, parts[size_t(s)]); };
    if (n < 1024)
        for (int s = 0; s < kStripes; ++s) run(s);
    else
        cv::parallel_for_(
            cv::Range(0, kStripes),
            [&](const cv::Range& r) {
                for (int s = r.start; s < r.end; ++s) run(s);
            },
            kStripes);
    Part total = parts[0];
    for (int s = 1; s < kStripes; ++s) total += parts[size_t(s)];
    return total;
}

}  // namespace quasiloc::estimation::detail
