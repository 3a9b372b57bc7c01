// StereoPairer (stereo_pairing.h).
#include <cstdlib>
#include <quasiloc/core/error.h>
#include <quasiloc/dataset/stereo_pairing.h>

namespace quasiloc::dataset
{
StereoPairer::StereoPairer(std::int64_t tolerance_ns, std::size_t max_pending)
    : tolerance_ns_(tolerance_ns), max_pending_(max_pending)
{
    core::require(tolerance_ns >= 0, "StereoPairer", "the tolerance must not be negative");
    core::require(max_pending >= 1, "StereoPairer", "max_pending must be at least 1");
}

void StereoPairer::add(bool left, std::int64_t t_ns, std::size_t id)
{
    const int s = left ? 0 : 1;
    if (seen_[s] && t_ns <= latest_ns_[s])
    {
        unpaired_.push_back({left, t_ns, id, true});
        ++num_unpaired_[s];
        return;
    }
    seen_[s] = true;
    latest_ns_[s] = t_ns;
    pending_[s].push_back({t_ns, id});
    match();
    while (pending_[s].size() > max_pending_) dropFront(left);
}

void StereoPairer::dropFront(bool left)
{
    const int s = left ? 0 : 1;
    const Pending p = pending_[s].front();
    pending_[s].pop_front();
    unpaired_.push_back({left, p.t_ns, p.id, false});
    ++num_unpaired_[s];
}

void StereoPairer::match()
{
    auto& L = pending_[0];
    auto& R = pending_[1];
    for (;;)
    {
        if (!L.empty() && !R.empty())
        {
            const std::int64_t dt = L.front().t_ns - R.front().t_ns;
            if (std::llabs(dt) <= tolerance_ns_)
            {
                pairs_.push_back({L.front().t_ns, R.front().t_ns, L.front().id, R.front().id});
                ++num_pairs_;
                L.pop_front();
                R.pop_front();
            }
            else
                dropFront(dt < 0);  // the earlier one: every later image of the other side is farther away
            continue;
        }
        // One side waits: it can still pair unless the other side has already gone past it.
        if (!L.empty() && seen_[1] && latest_ns_[1] > L.front().t_ns + tolerance_ns_)
            dropFront(true);
        else if (!R.empty() && seen_[0] && latest_ns_[0] > R.front().t_ns + tolerance_ns_)
            dropFront(false);
        else
            return;
    }
}

void StereoPairer::finish()
{
    while (!pending_[0].empty()) dropFront(true);
    while (!pending_[1].empty()) dropFront(false);
}

std::vector<StereoPairer::Pair> StereoPairer::takePairs()
{
    std::vector<Pair> out;
    out.swap(pairs_);
    return out;
}

std::vector<StereoPairer::Unpaired> StereoPairer::takeUnpaired()
{
    std::vector<Unpaired> out;
    out.swap(unpaired_);
    return out;
}

}  // namespace quasiloc::dataset
