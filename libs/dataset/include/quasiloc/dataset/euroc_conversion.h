#pragma once
// EuRoC ASL folder -> MRPT rawlog (+ <name>_Images/), calibration INI and ground-truth TUM file.
// The work of the program euroc2rawlog, in the library so that tests can run it.
#include <mrpt/system/CTimeLogger.h>

#include <cstdint>
#include <quasiloc/core/declared_options.h>
#include <string>
#include <vector>

namespace quasiloc::dataset
{
/** INI section [Euroc2Rawlog]; each key's unit, range and meaning: declare() (euroc_conversion.cpp). */
struct Euroc2RawlogOptions : public core::DeclaredOptions
{
    std::string input;
    std::string output;
    std::string groundtruth;
    std::string calib_out;
    std::string gt_out;
    std::string imu_yaml;
    std::string stereo_sensor_label = "stereo";
    std::string imu_sensor_label = "imu";
    int max_frames = 0;
    double gt_margin_s = 1.0;
    int gz_compression_level = 1;

    void declare(core::OptionTable& t) override;
    /** The declared ranges, then InputError naming "[Euroc2Rawlog] <key>" for a missing input/output or a bad value. */
    void check() const;

    std::string calibOutPath() const;  ///< calib_out or its default
    std::string gtOutPath() const;     ///< gt_out or its default (only written when groundtruth is set)
};

struct Euroc2RawlogResult
{
    size_t stereo_written = 0, imu_written = 0;
    size_t cam0_rows = 0, cam1_rows = 0, imu_rows = 0;
    std::vector<std::string> skipped_rows_report;  ///< from EurocSequence::skippedRowsReport()
    size_t skipped_rows = 0;
    std::string rawlog_path, images_folder, calib_path, gt_path;  ///< gt_path empty without ground truth
    std::string imu_yaml;                  ///< where the calibration's [imu] noise model came from
    std::string gt_kind;                   ///< "TUM T_world_cam0" or "EuRoC body csv x T_body_cam0"
    size_t gt_poses_written = 0;           ///< poses in the written TUM file
    size_t gt_duplicate_rows_dropped = 0;  ///< rows of the whole input file repeating an earlier timestamp
    size_t frames_with_gt = 0;             ///< written frames whose timestamp has a ground-truth pose (within 5 ms)
    double first_frame_t = 0, last_frame_t = 0, gt_first_t = 0, gt_last_t = 0;
};

/** Converts; everything is read and checked before anything is written, and the rawlog with its images
 *  appears only when complete. Stages are timed in `timer` when given. */
Euroc2RawlogResult convertEurocToRawlog(const Euroc2RawlogOptions& options, mrpt::system::CTimeLogger* timer = nullptr);

}  // namespace quasiloc::dataset
