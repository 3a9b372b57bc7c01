#pragma once
// The EuRoC ASL folder layout (mav0/cam0, mav0/cam1, mav0/imu0), read into an index of stereo pairs and
// IMU samples with integer-nanosecond timestamps. Images are not decoded here: the pairs name the PNG
// files, so a converter can copy them and a FrameSource can decode them one frame at a time.
#include <cstdint>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/dataset/frame.h>
#include <string>
#include <vector>

namespace quasiloc::dataset
{
struct EurocStereoPair
{
    std::int64_t t_ns = 0;
    std::string left_png, right_png;  ///< absolute or as given: <mav0>/cam0/data/<file>
};

/** Rows of the csv files that did not become part of a stereo pair, grouped by reason. */
struct EurocSkippedRows
{
    std::string reason;              ///< e.g. "cam1/data.csv rows whose image file is missing"
    std::vector<std::int64_t> t_ns;  ///< the rows' timestamps
};

struct EurocSequence
{
    std::string mav0_folder;
    core::StereoRig rig;                 ///< from cam0/sensor.yaml (left) and cam1/sensor.yaml (right); body = IMU
    std::vector<EurocStereoPair> pairs;  ///< sorted by time
    std::vector<std::int64_t> imu_t_ns;  ///< sorted by time, parallel to imu
    std::vector<ImuSample> imu;          ///< t in seconds from imu_t_ns
    size_t cam0_rows = 0, cam1_rows = 0;
    std::vector<EurocSkippedRows> skipped;  ///< only non-empty groups

    size_t numSkippedRows() const;
    /** One line per group: "<count> <reason> (skipped): t_ns=..., ..." (first few timestamps). */
    std::vector<std::string> skippedRowsReport() const;
};

/** Path of mav0/ for an ASL folder given either as the folder holding mav0/ or as mav0/ itself;
 *  InputError naming the folder if neither holds cam0/. */
std::string eurocMav0Folder(const std::string& asl_folder);

/** Reads the csv and yaml files of an ASL folder. A stereo pair is a cam0 row whose image file exists and
 *  whose timestamp has a cam1 row with an existing image file; other rows are skipped and recorded in
 *  `skipped`. Malformed csv lines, missing csv/yaml files or an empty result are InputErrors naming the
 *  file (and line). imu0/data.csv is read by readEurocImuCsv (euroc_imu_csv.h) at the nominal 200 Hz, with
 *  its checks (time order, duplicates, gaps over 2.5 periods). */
EurocSequence readEurocSequence(const std::string& asl_folder);

}  // namespace quasiloc::dataset
