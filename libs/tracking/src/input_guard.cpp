#include <quasiloc/tracking/input_guard.h>

#include <algorithm>
#include <cmath>
#include <iomanip>

namespace quasiloc::tracking
{
void InputGuard::closeEpisode()
{
    if (episode_frames_ == 0) return;
    out_ << "input fault over: " << episode_frames_ << " frame(s) not tracked (" << episode_reason_ << ", t "
         << std::fixed << std::setprecision(3) << episode_first_t_ << " .. " << episode_last_t_ << ")" << std::endl;
    episode_frames_ = 0;
    episode_reason_.clear();
}

bool InputGuard::accept(dataset::StereoFrame& f)
{
    // IMU samples that do not advance (repeated, or older than one passed on) are dropped; new ones are kept.
    std::vector<dataset::ImuSample> samples = std::move(carried_);
    carried_.clear();
    for (const auto& s : f.imu)
    {
        const double newest = !samples.empty() ? samples.back().t : last_imu_t_ ? *last_imu_t_ : -INFINITY;
        if (s.t > newest) samples.push_back(s);
    }
    const char* reason = nullptr;
    if (last_t_ && !(f.timestamp > *last_t_))
        reason = f.timestamp == *last_t_ ? "duplicated timestamp" : "timestamp earlier than the previous frame's";
    else if (last_t_ && samples.empty())
        reason = "no IMU sample since the previous frame (an IMU gap)";
    if (reason)
    {
        carried_ = std::move(samples);
        if (episode_reason_ != reason)
        {
            closeEpisode();
            out_ << "input fault: frame " << f.index << " at t " << std::fixed << std::setprecision(6) << f.timestamp
                 << " rejected: " << reason << " (last frame tracked at t " << *last_t_ << "); not tracked"
                 << std::endl;
            episode_reason_ = reason;
            episode_first_t_ = f.timestamp;
        }
        ++episode_frames_, ++rejected_total_;
        episode_last_t_ = f.timestamp;
        after_rejection_ = true;
        return false;
    }
    closeEpisode();
    rejected_before_last_ = after_rejection_;
    after_rejection_ = false;
    // The longest hole without IMU before this frame: from the last sample passed on, between samples, to the frame.
    imu_gap_s_ = 0;
    double prev = last_imu_t_ ? *last_imu_t_ : (samples.empty() ? f.timestamp : samples.front().t);
    for (const auto& s : samples) imu_gap_s_ = std::max(imu_gap_s_, s.t - prev), prev = s.t;
    imu_gap_s_ = std::max(imu_gap_s_, f.timestamp - prev);
    frame_gap_s_ = last_t_ ? f.timestamp - *last_t_ : 0;
    if (!samples.empty()) last_imu_t_ = samples.back().t;
    f.imu = std::move(samples);
    last_t_ = f.timestamp;
    return true;
}

bool InputGuard::lastWasFaulty(double max_gap_s) const
{
    return rejected_before_last_ || frame_gap_s_ > max_gap_s || imu_gap_s_ > max_gap_s;
}

}  // namespace quasiloc::tracking
