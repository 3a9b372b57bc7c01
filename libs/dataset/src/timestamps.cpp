#include <cmath>
#include <stdexcept>
#include <string>
#include <quasiloc/dataset/timestamps.h>

namespace quasiloc::dataset
{
namespace
{
constexpr std::int64_t kNsPerSecond = 1000000000;
constexpr std::int64_t kNsPerTick = 100;

// MRPT counts 100 ns ticks from its own epoch; fromDouble(0) is exactly the Unix epoch in that count.
std::int64_t mrptUnixEpochTicks()
{
    static const std::int64_t ticks = mrpt::Clock::fromDouble(0.0).time_since_epoch().count();
    return ticks;
}
}  // namespace

double nsToSeconds(std::int64_t t_ns)
{
    const std::int64_t s = t_ns / kNsPerSecond;
    const std::int64_t rest = t_ns % kNsPerSecond;
    return static_cast<double>(s) + static_cast<double>(rest) * 1e-9;
}

std::int64_t secondsToNs(double t_s)
{
    const double whole = std::floor(t_s);
    return static_cast<std::int64_t>(whole) * kNsPerSecond + std::llround((t_s - whole) * 1e9);
}

mrpt::Clock::time_point mrptTimeFromNs(std::int64_t t_ns)
{
    // Round to the nearest tick (floor division keeps it right for times before 1970 too).
    std::int64_t q = (t_ns + kNsPerTick / 2) / kNsPerTick;
    if ((t_ns + kNsPerTick / 2) % kNsPerTick < 0) --q;
    return mrpt::Clock::time_point(mrpt::Clock::duration(mrptUnixEpochTicks() + q));
}

std::optional<std::int64_t> mrptTimeToNsChecked(mrpt::Clock::time_point t)
{
    // A corrupt rawlog can hold any tick count (found by fuzz_rawlog): the ns count must not overflow int64.
    std::int64_t ticks_since_unix = 0, t_ns = 0;
    if (__builtin_sub_overflow(t.time_since_epoch().count(), mrptUnixEpochTicks(), &ticks_since_unix) ||
        __builtin_mul_overflow(ticks_since_unix, kNsPerTick, &t_ns))
        return std::nullopt;
    return t_ns;
}

std::int64_t mrptTimeToNs(mrpt::Clock::time_point t)
{
    const auto t_ns = mrptTimeToNsChecked(t);
    if (!t_ns)
        throw std::out_of_range("MRPT timestamp of " + std::to_string(t.time_since_epoch().count()) +
                                " ticks is more than 292 years from 1970 (not representable in int64 ns)");
    return *t_ns;
}

double mrptTimeToSeconds(mrpt::Clock::time_point t) { return nsToSeconds(mrptTimeToNs(t)); }

}  // namespace quasiloc::dataset
