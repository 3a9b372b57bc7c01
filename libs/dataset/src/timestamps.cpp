#include <cmath>
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

std::int64_t mrptTimeToNs(mrpt::Clock::time_point t)
{
    return (t.time_since_epoch().count() - mrptUnixEpochTicks()) * kNsPerTick;
}

double mrptTimeToSeconds(mrpt::Clock::time_point t)
{
    return nsToSeconds(mrptTimeToNs(t));
}

}  // namespace quasiloc::dataset
