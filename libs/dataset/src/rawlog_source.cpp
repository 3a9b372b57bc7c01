// openRawlog(): a FrameSource streaming an MRPT rawlog, one observation at a time.
#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cstring>
#include <deque>
#include <filesystem>
#include <map>
#include <quasiloc/core/error.h>
#include <quasiloc/dataset/calibration.h>
#include <quasiloc/dataset/frame_source.h>
#include <quasiloc/dataset/ground_truth.h>
#include <quasiloc/dataset/rawlog_writer.h>
#include <quasiloc/dataset/timestamps.h>

#include "image_checks.h"

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
    mrpt::obs::CObservationStereoImages::Ptr obs;
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
        : path_(path), images_folder_(rawlogImagesFolder(path)), arch_(in_), max_gt_dt_s_(options.max_gt_dt_s)
    {
        require(fs::is_regular_file(path), path, "rawlog file not found");
        require(in_.open(path), path, "cannot open rawlog");
        // For code that loads the observations' external images through mrpt::img::CImage. Our own decoding
        // below resolves the paths itself and does not depend on this process-wide setting.
        mrpt::img::CImage::setImagesPathBase(images_folder_);
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
    static core::StereoRig rigOf(const mrpt::obs::CObservationStereoImages& obs, const std::string& input)
    {
        core::StereoRig rig;
        rig.left = core::CameraModel::fromTCamera(obs.leftCamera);
        rig.right = core::CameraModel::fromTCamera(obs.rightCamera);
        rig.T_left_right = mrpt::poses::CPose3D(obs.rightCameraPose);
        rig.T_body_left = mrpt::poses::CPose3D(obs.cameraPose);
        rig.check(input);
        return rig;
    }

    void readOne();
    void handle(const mrpt::obs::CObservation::Ptr& obs, size_t entry);
    cv::Mat decode(const mrpt::img::CImage& img, const core::CameraModel& cam, const std::string& camera_name,
                   size_t entry) const;

    std::string path_, images_folder_;
    mrpt::io::CFileGZInputStream in_;
    mrpt::serialization::CArchiveStreamBase<mrpt::io::CFileGZInputStream> arch_;
    size_t entry_ = 0;
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
    mrpt::obs::CActionCollection::Ptr action;
    mrpt::obs::CSensoryFrame::Ptr sf;
    mrpt::obs::CObservation::Ptr obs;
    const uint64_t pos_before = in_.getPosition();
    const size_t entry = entry_;
    if (!mrpt::obs::CRawlog::getActionObservationPairOrObservation(arch_, action, sf, obs, entry_))
    {
        // MRPT returns false both at the end and on a read error; a clean end consumed no byte.
        require(in_.getPosition() == pos_before, path_,
                "corrupt or truncated rawlog: cannot read entry " + std::to_string(entry) + " (at byte " +
                    std::to_string(pos_before) + " of the uncompressed stream)");
        eof_ = true;
        return;
    }
    if (obs) handle(obs, entry);
    if (sf)
        for (const auto& o : *sf) handle(o, entry);
}

/** MRPT reads some bools of an observation as raw bytes (CObservationIMU::dataIsPresent,
 *  CObservationStereoImages::hasImageRight): a corrupt file can hold a byte that is no valid bool (0 or 1), and
 *  loading it is undefined behaviour (found by fuzz_rawlog: bytes 177 and 5). Any non-zero byte means true. */
void normaliseBool(bool& flag)
{
    unsigned char byte = 0;
    std::memcpy(&byte, &flag, 1);
    flag = byte != 0;
}

void RawlogSource::handle(const mrpt::obs::CObservation::Ptr& obs, size_t entry)
{
    using namespace mrpt::obs;
    const auto t_ns_checked = mrptTimeToNsChecked(obs->timestamp);
    require(t_ns_checked.has_value(), path_,
            "entry " + std::to_string(entry) + ": timestamp of " +
                std::to_string(obs->timestamp.time_since_epoch().count()) +
                " MRPT ticks is more than 292 years from 1970 (corrupt file)");
    const std::int64_t t_ns = *t_ns_checked;
    last_read_t_ns_ = t_ns;
    if (auto stereo = std::dynamic_pointer_cast<CObservationStereoImages>(obs))
    {
        normaliseBool(stereo->hasImageRight);
        if (!stereo->hasImageRight)
        {
            ++stereo_without_right_;
            return;
        }
        stereo_.push_back({t_ns, entry, stereo});
    }
    else if (auto imu = std::dynamic_pointer_cast<CObservationIMU>(obs))
    {
        for (auto& flag : imu->dataIsPresent) normaliseBool(flag);
        const bool complete = imu->has(IMU_X_ACC) && imu->has(IMU_Y_ACC) && imu->has(IMU_Z_ACC) && imu->has(IMU_WX) &&
                              imu->has(IMU_WY) && imu->has(IMU_WZ);
        if (!complete)
        {
            ++imu_incomplete_;
            return;
        }
        TimedImu s{t_ns, {}};
        s.sample.t = nsToSeconds(t_ns);
        s.sample.acc = {imu->get(IMU_X_ACC), imu->get(IMU_Y_ACC), imu->get(IMU_Z_ACC)};
        s.sample.gyro = {imu->get(IMU_WX), imu->get(IMU_WY), imu->get(IMU_WZ)};
        imu_.push_back(s);
    }
    else
        ++ignored_classes_[obs->GetRuntimeClass()->className];
}

cv::Mat RawlogSource::decode(const mrpt::img::CImage& img, const core::CameraModel& cam, const std::string& camera_name,
                             size_t entry) const
{
    const std::string where = path_ + " (entry " + std::to_string(entry) + ", " + camera_name + " image)";
    if (!img.isExternallyStored())
    {
        require(!img.isEmpty(), where, "embedded image is empty");
        return detail::toGrayOfCameraSize(img.asCvMat<cv::Mat>(mrpt::img::DEEP_COPY), cam, where, camera_name);
    }
    const fs::path file(img.getExternalStorageFile());
    const std::string full = file.is_absolute() ? file.string() : (fs::path(images_folder_) / file).string();
    cv::Mat out = detail::loadGrayImage(full, cam, camera_name);
    img.unload();  // no-op unless someone loaded it through CImage; the observation is dropped next anyway
    return out;
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
    frame.left = decode(s.obs->imageLeft, rig_.left, "left", s.entry);
    frame.right = decode(s.obs->imageRight, rig_.right, "right", s.entry);

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
