#pragma once
// Timestamps as integer nanoseconds, double seconds and MRPT Clock time points. A Unix time in ns
// (~1.4e18) does not fit a double's 53-bit mantissa, so conversions split seconds and nanoseconds.
#include <mrpt/core/Clock.h>

#include <cstdint>
#include <optional>

namespace quasiloc::dataset
{
/** Seconds with only the final rounding (about 0.1 us at 1.4e9 s). */
double nsToSeconds(std::int64_t t_ns);
/** Nearest integer nanoseconds of a time in seconds. */
std::int64_t secondsToNs(double t_s);

/** MRPT time point (100 ns ticks) nearest to t_ns. */
mrpt::Clock::time_point mrptTimeFromNs(std::int64_t t_ns);
/** Nanoseconds since the Unix epoch of an MRPT time point; std::out_of_range when that does not fit an int64
 *  (more than 292 years from 1970: only a corrupt file holds such a time). */
std::int64_t mrptTimeToNs(mrpt::Clock::time_point t);
/** Like mrptTimeToNs, but nullopt instead of the exception: for readers that report the file and entry. */
std::optional<std::int64_t> mrptTimeToNsChecked(mrpt::Clock::time_point t);
/** Like mrpt::Clock::toDouble but without its rounding of the tick count to a double first. */
double mrptTimeToSeconds(mrpt::Clock::time_point t);

}  // namespace quasiloc::dataset
