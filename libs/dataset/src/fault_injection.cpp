#include <quasiloc/core/error.h>
#include <quasiloc/dataset/fault_injection.h>

#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace quasiloc::dataset
{
using core::Range;

void FaultInjectionOptions::declare(core::OptionTable& t)
{
    t.add("seed", seed, "", Range::atLeast(0), "test facility (docs/reliability.md): the random frame drops' seed");
    t.add("drop_from_s", drop_from_s, "s", Range::any(),
          "dropped frames from this long after the first frame (< 0: none); their IMU samples are kept");
    t.add("drop_duration_s", drop_duration_s, "s", Range::above(0), "... for this long");
    t.add("drop_ratio", drop_ratio, "", Range::between(0, 1), "... this share of them, at random (1: a burst)");
    t.add("imu_gap_from_s", imu_gap_from_s, "s", Range::any(), "IMU samples removed from this time (< 0: none)");
    t.add("imu_gap_duration_s", imu_gap_duration_s, "s", Range::above(0), "... for this long");
    t.addEnum("image_fault", image_fault,
              {{"none", ImageFault::None}, {"black", ImageFault::Black}, {"saturated", ImageFault::Saturated}},
              "what both images become in the image fault's window");
    t.add("image_from_s", image_from_s, "s", Range::any(), "black or saturated images from this time (< 0: none)");
    t.add("image_duration_s", image_duration_s, "s", Range::above(0), "... for this long");
    t.add("desync_from_s", desync_from_s, "s", Range::any(),
          "the right image as if exposed desync_ms later (turned by the gyroscope's rate) from this time (< 0: none)");
    t.add("desync_duration_s", desync_duration_s, "s", Range::above(0), "... for this long");
    t.add("desync_ms", desync_ms, "ms", Range::above(0),
          "... by this much (the rotation only: the translation over it is left out)");
    t.add("duplicate_at_s", duplicate_at_s, "s", Range::any(),
          "the frame at this time is yielded twice with the same timestamp (< 0: never)");
    t.add("reorder_at_s", reorder_at_s, "s", Range::any(),
          "the frame at this time is yielded after the next one (< 0: never)");
}

bool FaultInjectionOptions::any() const
{
    return drop_from_s >= 0 || imu_gap_from_s >= 0 || (image_from_s >= 0 && image_fault != ImageFault::None) ||
           desync_from_s >= 0 || duplicate_at_s >= 0 || reorder_at_s >= 0;
}

std::vector<std::string> FaultInjectionOptions::describe() const
{
    std::vector<std::string> lines;
    auto window = [](double from, double duration) {
        std::ostringstream s;
        s << std::setprecision(4) << "[" << from << ", " << from + duration << ") s";
        return s.str();
    };
    if (drop_from_s >= 0)
        lines.push_back("dropped frames: " + std::to_string(int(std::lround(100 * drop_ratio))) + " % at " +
                        window(drop_from_s, drop_duration_s) + " (seed " + std::to_string(seed) + ")");
    if (imu_gap_from_s >= 0) lines.push_back("IMU gap: no sample at " + window(imu_gap_from_s, imu_gap_duration_s));
    if (image_from_s >= 0 && image_fault != ImageFault::None)
        lines.push_back(std::string(image_fault == ImageFault::Black ? "black" : "saturated") + " images at " +
                        window(image_from_s, image_duration_s));
    if (desync_from_s >= 0)
        lines.push_back("left/right desync: the right image turned as " + std::to_string(int(std::lround(desync_ms))) +
                        " ms later at " + window(desync_from_s, desync_duration_s));
    if (duplicate_at_s >= 0) lines.push_back("duplicated timestamp at " + std::to_string(duplicate_at_s) + " s");
    if (reorder_at_s >= 0) lines.push_back("out-of-order frame at " + std::to_string(reorder_at_s) + " s");
    return lines;
}

FaultInjectingSource::FaultInjectingSource(std::unique_ptr<FrameSource> inner, const FaultInjectionOptions& options)
    : inner_(std::move(inner)), o_(options), rng_(options.seed)
{
    core::require(bool(inner_), "FaultInjectingSource", "no source to read from");
    o_.checkRanges("FaultInjectingSource", "FaultInjection");
}

std::string FaultInjectingSource::description() const
{
    std::string d = inner_->description() + " with injected faults (test facility):";
    for (const auto& line : o_.describe()) d += "\n  " + line;
    return d;
}

std::vector<std::string> FaultInjectingSource::warnings() const
{
    std::vector<std::string> w = inner_->warnings();
    for (const auto& [fault, t] : touched_)
    {
        std::ostringstream s;
        s << std::fixed << std::setprecision(3) << "injected fault: " << fault << ": " << t.frames << " frame(s), t "
          << t.first_s << " .. " << t.last_s << " s after the first frame";
        w.push_back(s.str());
    }
    return w;
}

bool FaultInjectingSource::fill(size_t count)
{
    while (ahead_.size() < count)
    {
        StereoFrame f;
        if (!inner_->next(f)) return false;
        if (!have_t0_) t0_ = f.timestamp, have_t0_ = true;
        ahead_.push_back(std::move(f));
    }
    return true;
}

bool FaultInjectingSource::within(double t, double from_s, double duration_s) const
{
    return from_s >= 0 && rel(t) >= from_s && rel(t) < from_s + duration_s;
}

void FaultInjectingSource::record(const std::string& fault, const StereoFrame& f)
{
    auto it = std::find_if(touched_.begin(), touched_.end(), [&](const auto& e) { return e.first == fault; });
    if (it == touched_.end())
    {
        touched_.push_back({fault, {0, rel(f.timestamp), rel(f.timestamp)}});
        it = touched_.end() - 1;
    }
    ++it->second.frames;
    it->second.last_s = rel(f.timestamp);
}

void FaultInjectingSource::removeImuGap(StereoFrame& f)
{
    const size_t before = f.imu.size();
    f.imu.erase(
        std::remove_if(f.imu.begin(), f.imu.end(),
                       [this](const ImuSample& s) { return within(s.t, o_.imu_gap_from_s, o_.imu_gap_duration_s); }),
        f.imu.end());
    if (f.imu.size() != before) record("IMU samples removed", f);
}

void FaultInjectingSource::applyImageFaults(StereoFrame& f)
{
    if (within(f.timestamp, o_.desync_from_s, o_.desync_duration_s))
    {
        f.right = desyncedRight(f);
        record("right image turned as desync_ms later", f);
    }
    if (o_.image_fault != ImageFault::None && within(f.timestamp, o_.image_from_s, o_.image_duration_s))
    {
        const double value = o_.image_fault == ImageFault::Black ? 0 : 255;
        f.left = cv::Mat(f.left.size(), f.left.type(), cv::Scalar::all(value));
        f.right = cv::Mat(f.right.size(), f.right.type(), cv::Scalar::all(value));
        record(o_.image_fault == ImageFault::Black ? "black images" : "saturated images", f);
    }
}

cv::Mat FaultInjectingSource::desyncedRight(const StereoFrame& f)
{
    // The right camera exposed desync_ms later has turned by the angular rate times desync_ms: its pixel u sees the
    // ray dR * b(u) of the camera at t (dR = exp(w_cam dt), b the pixel's bearing), which the image at t shows at
    // project(dR * b(u)). The rate is the gyroscope's mean over the frame's samples (its bias included, as a real
    // desync would see it).
    const core::CameraModel& camera = rig().right;
    if (right_bearings_.empty())
    {
        right_bearings_.reserve(size_t(camera.width) * size_t(camera.height));
        for (int v = 0; v < camera.height; ++v)
            for (int u = 0; u < camera.width; ++u) right_bearings_.push_back(camera.unprojectBearing({u, v}));
    }
    if (!f.imu.empty())
    {
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        for (const auto& s : f.imu) sum += s.gyro;
        last_gyro_ = sum / double(f.imu.size());
    }
    const Eigen::Matrix3d R_body_right = rig().T_body_right().getRotationMatrix().asEigen();
    const Eigen::Vector3d w_cam = R_body_right.transpose() * last_gyro_;
    const double angle = w_cam.norm() * o_.desync_ms * 1e-3;
    const Eigen::Matrix3d dR =
        angle > 0 ? Eigen::AngleAxisd(angle, w_cam.normalized()).toRotationMatrix() : Eigen::Matrix3d::Identity();
    cv::Mat map_x(camera.height, camera.width, CV_32FC1), map_y(camera.height, camera.width, CV_32FC1);
    for (int v = 0; v < camera.height; ++v)
        for (int u = 0; u < camera.width; ++u)
        {
            Eigen::Vector2d px(-1, -1);
            if (!camera.project(dR * right_bearings_[size_t(v) * size_t(camera.width) + size_t(u)], px)) px = {-1, -1};
            map_x.at<float>(v, u) = float(px.x());
            map_y.at<float>(v, u) = float(px.y());
        }
    cv::Mat out;
    cv::remap(f.right, out, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar::all(0));
    return out;
}

bool FaultInjectingSource::next(StereoFrame& out)
{
    if (!pending_.empty())
    {
        out = std::move(pending_.front());
        pending_.pop_front();
        out.index = yielded_++;
        return true;
    }
    std::uniform_real_distribution<double> uniform(0, 1);
    for (;;)
    {
        if (!fill(1)) return false;
        StereoFrame f = std::move(ahead_.front());
        ahead_.pop_front();
        removeImuGap(f);
        // A dropped frame's IMU samples come with the next frame yielded.
        f.imu.insert(f.imu.begin(), carried_imu_.begin(), carried_imu_.end());
        carried_imu_.clear();
        if (within(f.timestamp, o_.drop_from_s, o_.drop_duration_s) && uniform(rng_) < o_.drop_ratio)
        {
            record("dropped frames", f);
            carried_imu_ = std::move(f.imu);
            continue;
        }
        applyImageFaults(f);
        if (!reordered_ && o_.reorder_at_s >= 0 && rel(f.timestamp) >= o_.reorder_at_s && fill(1))
        {
            // The next frame first, with both frames' IMU samples (the IMU stream stays in order); this one after.
            reordered_ = true;
            StereoFrame later = std::move(ahead_.front());
            ahead_.pop_front();
            removeImuGap(later);
            applyImageFaults(later);
            later.imu.insert(later.imu.begin(), f.imu.begin(), f.imu.end());
            f.imu.clear();
            record("frame yielded after the next one", f);
            pending_.push_back(std::move(f));
            f = std::move(later);
        }
        else if (!duplicated_ && o_.duplicate_at_s >= 0 && rel(f.timestamp) >= o_.duplicate_at_s)
        {
            duplicated_ = true;
            StereoFrame copy = f;
            copy.imu.clear();  // its samples were delivered with the original
            record("frame yielded twice", f);
            pending_.push_back(std::move(copy));
        }
        out = std::move(f);
        out.index = yielded_++;
        return true;
    }
}

}  // namespace quasiloc::dataset
