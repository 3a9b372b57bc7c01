#include <algorithm>
#include <filesystem>
#include <optional>
#include <quasiloc/core/error.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/dataset/calibration.h>
#include <quasiloc/dataset/euroc.h>
#include <quasiloc/dataset/euroc_conversion.h>
#include <quasiloc/dataset/ground_truth.h>
#include <quasiloc/dataset/rawlog_writer.h>
#include <quasiloc/dataset/timestamps.h>

namespace fs = std::filesystem;
using quasiloc::core::require;

namespace quasiloc::dataset
{
namespace
{
const char* kSection = "[Euroc2Rawlog]";

std::string besideOutput(const std::string& output, const std::string& suffix)
{
    const fs::path p(output);
    return (p.parent_path() / (p.stem().string() + suffix)).string();
}

/** Times a stage when a logger is given. */
class Stage
{
   public:
    Stage(mrpt::system::CTimeLogger* timer, const char* name) : timer_(timer), name_(name)
    {
        if (timer_) timer_->enter(name_);
    }
    ~Stage()
    {
        if (timer_) timer_->leave(name_);
    }
    Stage(const Stage&) = delete;
    Stage& operator=(const Stage&) = delete;

   private:
    mrpt::system::CTimeLogger* timer_;
    const char* name_;
};

/** The frames' ground truth: restricted to their time span +- margin, with a header naming the frame. */
GroundTruthFile loadGroundTruth(const Euroc2RawlogOptions& o, const EurocSequence& seq, double t0, double t1)
{
    GroundTruthFile gt = readGroundTruthCam0(o.groundtruth, seq.rig.T_body_left);
    gt.T_world_cam0 = restrictToSpan(gt.T_world_cam0, t0, t1, o.gt_margin_s);
    require(!gt.T_world_cam0.poses.empty(), o.groundtruth,
            "no pose within the sequence's time span [" + std::to_string(t0) + ", " + std::to_string(t1) + "] s +- " +
                std::to_string(o.gt_margin_s) + " s (wrong sequence?)");
    gt.T_world_cam0.header =
        "T_world_cam0: pose of cam0 (the left camera of " + seq.mav0_folder + ") in the world frame\n" +
        (gt.kind == GroundTruthFile::Kind::TumCam0 ? "source: TUM file "
                                                   : "source: EuRoC body csv times T_body_cam0: ") +
        o.groundtruth + "\nt tx ty tz qx qy qz qw";
    return gt;
}

/** Writes IMU and stereo observations merged by time; an IMU sample stamped with a frame's time goes first. */
void writeInterleaved(RawlogWriter& writer, const EurocSequence& seq, size_t num_pairs, size_t num_imu)
{
    size_t i = 0, k = 0;
    while (i < num_pairs || k < num_imu)
    {
        if (k < num_imu && (i >= num_pairs || seq.imu_t_ns[k] <= seq.pairs[i].t_ns))
        {
            writer.writeImuNs(seq.imu_t_ns[k], seq.imu[k]);
            ++k;
        }
        else
        {
            const auto& p = seq.pairs[i++];
            writer.writeStereoFromPngFilesNs(p.t_ns, p.left_png, p.right_png);
        }
    }
}
}  // namespace

void Euroc2RawlogOptions::declare(core::OptionTable& t)
{
    using core::Range;
    t.add("input", input, "the EuRoC ASL folder (holding mav0/, or mav0/ itself)");
    t.add("output", output, "the rawlog to write; images go to <name>_Images/ beside it");
    t.add("groundtruth", groundtruth, "optional: TUM file of T_world_cam0 or EuRoC body csv (decided by content)");
    t.add("calib_out", calib_out, "calibration INI; empty = <output dir>/<name>_calib.ini");
    t.add("gt_out", gt_out, "ground truth TUM of T_world_cam0; empty = <output dir>/<name>_gt_cam0.tum");
    t.add("imu_yaml", imu_yaml,
          "the IMU's noise model (Kalibr / EuRoC sensor.yaml) for the calibration's [imu]; "
          "empty = <mav0>/imu0/sensor.yaml");
    t.add("stereo_sensor_label", stereo_sensor_label, "sensorLabel of the stereo observations");
    t.add("imu_sensor_label", imu_sensor_label, "sensorLabel of the IMU observations");
    t.add("max_frames", max_frames, "", Range::atLeast(0),
          "0 = every stereo pair; N = the first N pairs and the IMU samples up to the last of them (tests, previews)");
    t.add("gt_margin_s", gt_margin_s, "s", Range::atLeast(0),
          "ground truth is kept within the sequence's time span widened by this margin");
    t.add("gz_compression_level", gz_compression_level, "", Range::between(0, 9), "gzip level of the rawlog");
}

void Euroc2RawlogOptions::check() const
{
    checkRanges(kSection);
    require(!input.empty(), std::string(kSection) + " input", "is empty: give the EuRoC ASL folder");
    require(!output.empty(), std::string(kSection) + " output", "is empty: give the rawlog to write");
    require(!fs::is_directory(output), std::string(kSection) + " output", "'" + output + "' is a folder");
    require(!stereo_sensor_label.empty(), std::string(kSection) + " stereo_sensor_label", "is empty");
    require(!imu_sensor_label.empty(), std::string(kSection) + " imu_sensor_label", "is empty");
}

std::string Euroc2RawlogOptions::calibOutPath() const
{
    return calib_out.empty() ? besideOutput(output, "_calib.ini") : calib_out;
}

std::string Euroc2RawlogOptions::gtOutPath() const
{
    return gt_out.empty() ? besideOutput(output, "_gt_cam0.tum") : gt_out;
}

Euroc2RawlogResult convertEurocToRawlog(const Euroc2RawlogOptions& o, mrpt::system::CTimeLogger* timer)
{
    o.check();
    std::optional<Stage> stage(std::in_place, timer, "read EuRoC folder");
    const EurocSequence seq = readEurocSequence(o.input);
    Euroc2RawlogResult r;
    r.cam0_rows = seq.cam0_rows;
    r.cam1_rows = seq.cam1_rows;
    r.imu_rows = seq.imu.size();
    r.skipped_rows = seq.numSkippedRows();
    r.skipped_rows_report = seq.skippedRowsReport();

    const size_t num_pairs = o.max_frames > 0 ? std::min<size_t>(o.max_frames, seq.pairs.size()) : seq.pairs.size();
    size_t num_imu = seq.imu.size();
    if (o.max_frames > 0)
        num_imu = std::upper_bound(seq.imu_t_ns.begin(), seq.imu_t_ns.end(), seq.pairs[num_pairs - 1].t_ns) -
                  seq.imu_t_ns.begin();
    r.first_frame_t = nsToSeconds(seq.pairs.front().t_ns);
    r.last_frame_t = nsToSeconds(seq.pairs[num_pairs - 1].t_ns);

    // Everything that can fail on bad input is read before the first byte is written.
    SensorCalibration calibration;
    calibration.rig = seq.rig;
    r.imu_yaml = o.imu_yaml.empty() ? seq.mav0_folder + "/imu0/sensor.yaml" : o.imu_yaml;
    calibration.imu = imuCalibrationFromYaml(r.imu_yaml);
    std::optional<GroundTruthFile> gt;
    stage.emplace(timer, "read ground truth");
    if (!o.groundtruth.empty())
    {
        gt = loadGroundTruth(o, seq, r.first_frame_t, r.last_frame_t);
        r.gt_kind = gt->kind == GroundTruthFile::Kind::TumCam0 ? "TUM T_world_cam0" : "EuRoC body csv x T_body_cam0";
        r.gt_duplicate_rows_dropped = gt->duplicate_rows_dropped;
        r.gt_poses_written = gt->T_world_cam0.poses.size();
        r.gt_first_t = gt->T_world_cam0.poses.front().t;
        r.gt_last_t = gt->T_world_cam0.poses.back().t;
        for (size_t i = 0; i < num_pairs; ++i)
            if (poseAt(gt->T_world_cam0, nsToSeconds(seq.pairs[i].t_ns), 0.005)) ++r.frames_with_gt;
    }

    stage.emplace(timer, "write rawlog and images");
    RawlogWriter::Options wo;
    wo.stereo_sensor_label = o.stereo_sensor_label;
    wo.imu_sensor_label = o.imu_sensor_label;
    wo.gz_compression_level = o.gz_compression_level;
    RawlogWriter writer(o.output, seq.rig, wo);
    writeInterleaved(writer, seq, num_pairs, num_imu);
    writer.close();
    r.stereo_written = writer.numStereo();
    r.imu_written = writer.numImu();
    r.rawlog_path = writer.rawlogPath();
    r.images_folder = writer.imagesFolder();

    stage.emplace(timer, "write calibration and ground truth");
    r.calib_path = o.calibOutPath();
    saveCalibration(calibration, r.calib_path,
                    "Stereo rig of " + seq.mav0_folder +
                        " (cam0 = left, cam1 = right; body = IMU frame)\nIMU noise model of " + r.imu_yaml +
                        "; the biases were not measured (zero, with the sigmas of real MEMS biases)");
    if (gt)
    {
        r.gt_path = o.gtOutPath();
        core::writeTum(r.gt_path, gt->T_world_cam0);
    }
    return r;
}

}  // namespace quasiloc::dataset
