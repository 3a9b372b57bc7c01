// openEuroc(): a FrameSource over an EuRoC ASL folder.
#include <quasiloc/core/error.h>
#include <quasiloc/dataset/euroc.h>
#include <quasiloc/dataset/calibration.h>
#include <quasiloc/dataset/frame_source.h>
#include <quasiloc/dataset/ground_truth.h>
#include <quasiloc/dataset/timestamps.h>

#include "image_checks.h"

namespace quasiloc::dataset
{
namespace
{
class EurocSource : public FrameSource
{
   public:
    EurocSource(const std::string& asl_folder, const FrameSourceOptions& options)
        : seq_(readEurocSequence(asl_folder)), max_gt_dt_s_(options.max_gt_dt_s)
    {
        if (!options.calibration_ini.empty()) seq_.rig = loadCalibration(options.calibration_ini).rig;
        if (!options.groundtruth_tum.empty())
            gt_ = readGroundTruthCam0(options.groundtruth_tum, seq_.rig.T_body_left).T_world_cam0;
        warnings_ = seq_.skippedRowsReport();
    }

    const core::StereoRig& rig() const override { return seq_.rig; }

    bool next(StereoFrame& frame) override
    {
        if (next_pair_ >= seq_.pairs.size()) return false;
        const EurocStereoPair& pair = seq_.pairs[next_pair_];
        frame.index = next_pair_++;
        frame.timestamp = nsToSeconds(pair.t_ns);
        frame.left = detail::loadGrayImage(pair.left_png, seq_.rig.left, "left");
        frame.right = detail::loadGrayImage(pair.right_png, seq_.rig.right, "right");
        frame.imu.clear();
        // Samples with previous frame's t < t <= this frame's t (all up to it for the first frame).
        while (next_imu_ < seq_.imu.size() && seq_.imu_t_ns[next_imu_] <= pair.t_ns)
            frame.imu.push_back(seq_.imu[next_imu_++]);
        frame.T_world_cam0.reset();
        if (!gt_.poses.empty()) frame.T_world_cam0 = poseAt(gt_, frame.timestamp, max_gt_dt_s_);
        if (!frame.T_world_cam0 && !gt_.poses.empty()) ++frames_without_gt_;
        return true;
    }

    std::string description() const override { return "EuRoC ASL folder " + seq_.mav0_folder; }

    std::vector<std::string> warnings() const override
    {
        auto w = warnings_;
        if (frames_without_gt_ > 0)
            w.push_back(std::to_string(frames_without_gt_) + " frames without a ground-truth pose within " +
                        std::to_string(max_gt_dt_s_) + " s");
        return w;
    }

   private:
    EurocSequence seq_;
    double max_gt_dt_s_;
    core::Trajectory gt_;
    std::vector<std::string> warnings_;
    size_t next_pair_ = 0, next_imu_ = 0, frames_without_gt_ = 0;
};
}  // namespace

std::unique_ptr<FrameSource> openEuroc(const std::string& asl_folder, const FrameSourceOptions& options)
{
    return std::make_unique<EurocSource>(asl_folder, options);
}

}  // namespace quasiloc::dataset
