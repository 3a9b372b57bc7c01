#pragma once
// The tracking session's guard on the timing of its input. Sensors and drivers misbehave: a frame sent twice, frames
// out of order, a pause of the IMU. The tracker needs frames in time order, each with the IMU samples since the
// previous one, so the guard stands between the FrameSource and the session:
//   - a frame whose timestamp does not increase (duplicated, out of order) is rejected: it is not tracked, its IMU
//     samples are kept for the next frame when they are new (later than every sample passed on);
//   - a frame with no IMU sample since the previous frame (inside an IMU gap) is rejected the same way: without
//     the IMU it cannot be predicted;
//   - IMU samples that do not advance in time are dropped.
// Each fault is reported once on the console, naming its first frame and time, and again when it ends with the
// number of frames skipped; a run never stops for it. For what the session does after a fault (the track is
// unverified until a check confirms it), see tracking_session.h.
#include <optional>
#include <ostream>
#include <quasiloc/dataset/frame.h>
#include <string>
#include <vector>

namespace quasiloc::tracking
{
class InputGuard
{
   public:
    explicit InputGuard(std::ostream& console) : out_(console) {}

    /** True when `frame` may be tracked (its IMU samples are then those since the last frame accepted, carried
     *  ones first); false: rejected (reported, its new IMU samples carried to the next frame). */
    bool accept(dataset::StereoFrame& frame);
    /** The input of the last frame accepted was faulty: frames were rejected just before it, or its time since the
     *  previous accepted frame, or a hole in its IMU samples, exceeds `max_gap_s`. */
    bool lastWasFaulty(double max_gap_s) const;
    /** Time since the previous accepted frame, and the longest interval without an IMU sample before it [s]. */
    double lastFrameGapS() const { return frame_gap_s_; }
    double lastImuGapS() const { return imu_gap_s_; }
    size_t rejectedFrames() const { return rejected_total_; }

   private:
    /** Ends a run of rejected frames: one line with their count and times. */
    void closeEpisode();

    std::ostream& out_;
    std::optional<double> last_t_;      ///< the last frame accepted
    std::optional<double> last_imu_t_;  ///< the last IMU sample passed on
    std::vector<dataset::ImuSample> carried_;
    double frame_gap_s_ = 0, imu_gap_s_ = 0;
    bool after_rejection_ = false;       ///< frames were rejected since the last one accepted
    bool rejected_before_last_ = false;  ///< ... before the last one accepted
    /** The running episode of rejected frames (one reason at a time). */
    std::string episode_reason_;
    size_t episode_frames_ = 0, rejected_total_ = 0;
    double episode_first_t_ = 0, episode_last_t_ = 0;
};

}  // namespace quasiloc::tracking
