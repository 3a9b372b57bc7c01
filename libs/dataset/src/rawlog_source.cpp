// openRawlog(): a FrameSource streaming an MRPT rawlog, one entry at a time. The entries are read by our validating
// reader (rawlog_entries.h), which parses the classes used here itself instead of letting MRPT deserialize them.
#include <mrpt/obs/CObservationIMU.h>

#include <algorithm>
#include <deque>
#include <filesystem>
#include <map>
#include <quasiloc/core/error.h>
#include <quasiloc/dataset/calibration.h>
#include <quasiloc/dataset/frame_source.h>
#include <quasiloc/dataset/ground_truth.h>
#include <quasiloc/dataset/rawlog_writer.h>
#include <quasiloc/dataset/timestamps.h>

#include "embedded_jpeg.h"
#include "image_checks.h"
#include "rawlog_entries.h"

namespace fs = std::filesystem;
using quasiloc::core::require;

namespace quasiloc::dataset
{
namespace
{
struct PendingStereo
{
    std::int64_t t_ns;
    size_t entry;
    std::shared_ptr<const detail::StoredStereo> obs;
};

struct TimedImu
{
    std::int64_t t_ns;
    ImuSample sample;
};

class RawlogSource : public FrameSource
{
   public:
    RawlogSource(const std::string& path, const FrameSourceOptions& options)
        : path_(path), images_folder_(rawlogImagesFolder(path)), max_gt_dt_s_(options.max_gt_dt_s)
    {
        require(fs::is_regular_file(path), path, "rawlog file not found");
        entries_ = std::make_unique<detail::RawlogEntries>(path, options.mrpt_object_timeout_s);
        while (!eof_ && stereo_.empty()) readOne();
        require(!stereo_.empty(), path, "holds no CObservationStereoImages with a right image");
        if (!options.calibration_ini.empty())
            rig_ = loadCalibration(options.calibration_ini).rig;
        else
            rig_ = rigOf(*stereo_.front().obs, path + " (entry " + std::to_string(stereo_.front().entry) + ")");
        if (!options.groundtruth_tum.empty())
            gt_ = readGroundTruthCam0(options.groundtruth_tum, rig_.T_body_left).T_world_cam0;
    }

    const core::StereoRig& rig() const override { return rig_; }
    std::string description() const override { return "rawlog " + path_; }
    bool next(StereoFrame& frame) override;
    std::vector<std::string> warnings() const override;

   private:
    static core::StereoRig rigOf(const detail::StoredStereo& obs, const std::string& input)
    {
        core::StereoRig rig;
        rig.left = core::CameraModel::fromTCamera(obs.left_camera);
        rig.right = core::CameraModel::fromTCamera(obs.right_camera);
        rig.T_left_right = mrpt::poses::CPose3D(obs.right_camera_pose);
        rig.T_body_left = mrpt::poses::CPose3D(obs.camera_pose);
        rig.check(input);
        return rig;
    }

    void readOne();
    void handle(const detail::RawlogObservation& obs);
    cv::Mat decode(const detail::StoredImage& img, const core::CameraModel& cam, const std::string& camera_name,
                   size_t entry) const;

    std::string path_, images_folder_;
    std::unique_ptr<detail::RawlogEntries> entries_;
    std::vector<detail::RawlogObservation> read_;
    bool eof_ = false;
    std::int64_t last_read_t_ns_ = std::numeric_limits<std::int64_t>::min();
    std::deque<PendingStereo> stereo_;
    std::vector<TimedImu> imu_;
    std::optional<std::int64_t> last_frame_t_ns_;
    size_t index_ = 0;
    core::StereoRig rig_;
    core::Trajectory gt_;
    double max_gt_dt_s_;
    // Tolerated oddities, reported by warnings().
    std::map<std::string, size_t> ignored_classes_;
    size_t stereo_without_right_ = 0, imu_incomplete_ = 0, imu_late_ = 0, frames_without_gt_ = 0;
};

void RawlogSource::readOne()
{
    if (!entries_->next(read_))
    {
        eof_ = true;
        return;
    }
    for (const auto& o : read_) handle(o);
}

void RawlogSource::handle(const detail::RawlogObservation& obs)
{
    using namespace mrpt::obs;
    const auto t_ns_checked = mrptTimeToNsChecked(obs.timestamp);
    require(t_ns_checked.has_value(), path_,
            "entry " + std::to_string(obs.entry) + ": timestamp of " +
                std::to_string(obs.timestamp.time_since_epoch().count()) +
                " MRPT ticks is more than 292 years from 1970 (corrupt file)");
    const std::int64_t t_ns = *t_ns_checked;
    last_read_t_ns_ = t_ns;
    if (obs.stereo)
    {
        if (!obs.stereo->has_right)
        {
            ++stereo_without_right_;
            return;
        }
        stereo_.push_back({t_ns, obs.entry, obs.stereo});
    }
    else if (obs.imu)
    {
        const auto& present = obs.imu->present;
        const auto& value = obs.imu->values;
        const bool complete = present[IMU_X_ACC] && present[IMU_Y_ACC] && present[IMU_Z_ACC] && present[IMU_WX] &&
                              present[IMU_WY] && present[IMU_WZ];
        if (!complete)
        {
            ++imu_incomplete_;
            return;
        }
        TimedImu s{t_ns, {}};
        s.sample.t = nsToSeconds(t_ns);
        s.sample.acc = {value[IMU_X_ACC], value[IMU_Y_ACC], value[IMU_Z_ACC]};
        s.sample.gyro = {value[IMU_WX], value[IMU_WY], value[IMU_WZ]};
        imu_.push_back(s);
    }
    else
        ++ignored_classes_[obs.class_name];
}

cv::Mat RawlogSource::decode(const detail::StoredImage& img, const core::CameraModel& cam,
                             const std::string& camera_name, size_t entry) const
{
    using Kind = detail::StoredImage::Kind;
    const std::string where = path_ + " (entry " + std::to_string(entry) + ", " + camera_name + " image)";
    switch (img.kind)
    {
        case Kind::Empty: break;
        case Kind::Raw:
        {
            // The pixels' size was checked against the image size when the entry was read.
            const cv::Mat pixels(img.height, img.width, img.cv_type, const_cast<std::uint8_t*>(img.bytes.data()));
            return detail::toGrayOfCameraSize(pixels.clone(), cam, where, camera_name);
        }
        case Kind::Jpeg:
            return detail::toGrayOfCameraSize(detail::decodeEmbeddedJpeg(img.bytes, where, detail::kMaxImagePixels),
                                              cam, where, camera_name);
        case Kind::External:
        {
            const fs::path file(img.external_file);
            const std::string full = file.is_absolute() ? file.string() : (fs::path(images_folder_) / file).string();
            return detail::loadGrayImage(full, cam, camera_name);
        }
    }
    throw core::InputError(where, "embedded image is empty");
}

bool RawlogSource::next(StereoFrame& frame)
{
    // Read on until an observation later than the next stereo one: IMU samples stamped at the frame time
    // may follow the stereo observation in the stream.
    while (!eof_ && (stereo_.empty() || last_read_t_ns_ <= stereo_.front().t_ns)) readOne();
    if (stereo_.empty()) return false;
    const PendingStereo s = std::move(stereo_.front());
    stereo_.pop_front();
    require(!last_frame_t_ns_ || s.t_ns > *last_frame_t_ns_, path_,
            "stereo observation at entry " + std::to_string(s.entry) + " is not later than the previous one");

    frame.index = index_++;
    frame.timestamp = nsToSeconds(s.t_ns);
    frame.left = decode(s.obs->left, rig_.left, "left", s.entry);
    frame.right = decode(s.obs->right, rig_.right, "right", s.entry);

    std::stable_sort(imu_.begin(), imu_.end(), [](const TimedImu& a, const TimedImu& b) { return a.t_ns < b.t_ns; });
    const auto end = std::find_if(imu_.begin(), imu_.end(), [&](const TimedImu& x) { return x.t_ns > s.t_ns; });
    frame.imu.clear();
    for (auto it = imu_.begin(); it != end; ++it)
    {
        if (last_frame_t_ns_ && it->t_ns <= *last_frame_t_ns_)
            ++imu_late_;  // arrived after the frame it belongs to had been yielded
        else
            frame.imu.push_back(it->sample);
    }
    imu_.erase(imu_.begin(), end);
    last_frame_t_ns_ = s.t_ns;

    frame.T_world_cam0.reset();
    if (!gt_.poses.empty())
    {
        frame.T_world_cam0 = poseAt(gt_, frame.timestamp, max_gt_dt_s_);
        if (!frame.T_world_cam0) ++frames_without_gt_;
    }
    return true;
}

std::vector<std::string> RawlogSource::warnings() const
{
    std::vector<std::string> w;
    if (stereo_without_right_)
        w.push_back(std::to_string(stereo_without_right_) + " stereo observations without a right image (skipped)");
    if (imu_incomplete_)
        w.push_back(std::to_string(imu_incomplete_) +
                    " IMU observations without all 3 accelerations and 3 angular rates (skipped)");
    if (imu_late_) w.push_back(std::to_string(imu_late_) + " IMU samples older than the frame before them (dropped)");
    for (const auto& [name, n] : ignored_classes_)
        w.push_back(std::to_string(n) + " observations of class " + name + " (ignored)");
    if (entries_->endedAfterAction())
        w.push_back(
            "the file ends after an action collection without its sensory frame (the action is dropped, as "
            "MRPT's CRawlog does)");
    if (frames_without_gt_)
        w.push_back(std::to_string(frames_without_gt_) + " frames without a ground-truth pose within " +
                    std::to_string(max_gt_dt_s_) + " s");
    return w;
}
}  // namespace

std::unique_ptr<FrameSource> openRawlog(const std::string& rawlog_path, const FrameSourceOptions& options)
{
    return std::make_unique<RawlogSource>(rawlog_path, options);
}

}  // namespace quasiloc::dataset
