#pragma once
// Fault injection: a FrameSource decorator that makes a good recording misbehave the way real sensors do, so that
// the tracking session can be tested against dropped frames, IMU gaps, black or saturated images, a left/right
// desync and duplicated or out-of-order timestamps (docs/reliability.md). A test facility, not a product setting:
// every fault is off by default, and the tracker never knows it is there (the faults live in the data).
//
// Times are seconds after the first frame's timestamp; a fault with a negative start never happens. Each fault acts
// on a window [from_s, from_s + duration_s) of frame (or IMU sample) times:
//   dropped frames   drop_ratio of the window's frames are not yielded (seeded; 1 = a burst); their IMU samples are
//                    not lost but yielded with the next frame, as a camera that drops frames leaves the IMU alone;
//   IMU gap          the IMU samples inside the window are removed (frames inside it then carry none);
//   image fault      the left and right images are black (0) or saturated (255);
//   desync           the right image as the right camera would have seen it desync_ms later: turned by the
//                    gyroscope's rate times desync_ms (a remap through the camera model). It models a right camera
//                    whose trigger is late, on a platform that turns; the translation over desync_ms (2 cm at 1 m/s,
//                    a shift of 9 px / depth in m at EuRoC's focal length) is left out: it needs the scene's depth;
//   duplicate        the frame at duplicate_at_s is yielded twice with the same timestamp (the copy carries no IMU
//                    sample: a driver that sends a frame again);
//   out of order     the frame at reorder_at_s is yielded after the next one (the IMU stream stays in order: the
//                    later frame brings both frames' samples, the late one none).
#include <quasiloc/core/declared_options.h>
#include <quasiloc/dataset/frame_source.h>

#include <deque>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace quasiloc::dataset
{
enum class ImageFault
{
    None,
    Black,
    Saturated
};

/** [FaultInjection]: a test section of quasiloc-track; all off by default. */
struct FaultInjectionOptions : public core::DeclaredOptions
{
    size_t seed = 1;
    double drop_from_s = -1, drop_duration_s = 0.5, drop_ratio = 1;
    double imu_gap_from_s = -1, imu_gap_duration_s = 0.1;
    ImageFault image_fault = ImageFault::Black;
    double image_from_s = -1, image_duration_s = 1;
    double desync_from_s = -1, desync_duration_s = 1, desync_ms = 20;
    double duplicate_at_s = -1, reorder_at_s = -1;

    /** True when some fault is on. */
    bool any() const;
    /** One line per fault that is on, with its window ("dropped frames 50 % at [5, 7) s"). */
    std::vector<std::string> describe() const;
    void declare(core::OptionTable& t) override;
};

class FaultInjectingSource : public FrameSource
{
   public:
    /** Reads the frames of `inner`. InputError for options out of range. */
    FaultInjectingSource(std::unique_ptr<FrameSource> inner, const FaultInjectionOptions& options);

    const core::StereoRig& rig() const override { return inner_->rig(); }
    bool next(StereoFrame& frame) override;
    std::string description() const override;
    /** The inner source's warnings, then one line per fault injected (the frames and times it touched). */
    std::vector<std::string> warnings() const override;

   private:
    /** The inner source's next frame into the look-ahead (false at its end). */
    bool fill(size_t count);
    /** Seconds after the first frame. */
    double rel(double t) const { return t - t0_; }
    bool within(double t, double from_s, double duration_s) const;
    void applyImageFaults(StereoFrame& f);
    /** The right image turned by the rotation over desync_ms. */
    cv::Mat desyncedRight(const StereoFrame& f);
    void removeImuGap(StereoFrame& f);
    void record(const std::string& fault, const StereoFrame& f);

    std::unique_ptr<FrameSource> inner_;
    FaultInjectionOptions o_;
    std::mt19937_64 rng_;
    std::deque<StereoFrame> ahead_;                ///< read from inner_, not yet yielded (reorder)
    std::vector<Eigen::Vector3d> right_bearings_;  ///< desync: every right pixel's bearing (row-major)
    Eigen::Vector3d last_gyro_ = Eigen::Vector3d::Zero();
    std::vector<ImuSample> carried_imu_;  ///< the samples of dropped frames, for the next frame yielded
    std::deque<StereoFrame> pending_;     ///< to yield next (a duplicate, a late frame)
    double t0_ = 0;
    bool have_t0_ = false, duplicated_ = false, reordered_ = false;
    size_t yielded_ = 0;
    /** Per fault: frames touched, first and last frame time (relative). */
    struct Touched
    {
        size_t frames = 0;
        double first_s = 0, last_s = 0;
    };
    std::vector<std::pair<std::string, Touched>> touched_;
};

}  // namespace quasiloc::dataset
