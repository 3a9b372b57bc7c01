#pragma once
// The pose of every scan of a mapping run: T_world_lidar(t) = T_world_body(t) * T_body_lidar, with T_world_body
// from a trajectory file and t the scan's time.
//  - TUM trajectory ("t x y z qx qy qz qw" per line, T_world_body): each scan needs a time, from its file name
//    (the stem as a number, times time_scale: "1626343512.123.pcd", or nanoseconds "1626343512123456789.pcd" with
//    time_scale 1e-9), from a scan-times file (one time per line, in scan order) or the scan's index.
//    A bag's scans carry their own stamps (the PointCloud2 headers'), given to the constructor
//    (ScanTimeSource::Stamps).
//  - KITTI poses (a 3x4 row-major matrix per line, T_world_body): line k is frame k at time k * frame_period_s; a
//    scan's frame is its file name's number ("0000000042.bin" -> line 42), a scan-times file's line or its index.
//  - Stamped poses the caller read (TrajectoryFormat::Bag: a bag's pose topic, libs/ros readBagTrajectory), used as a
//    TUM trajectory is.
// Poses are interpolated (linear, slerp) between the two trajectory poses around a time; a time outside the
// trajectory, or between two poses further apart than max_pose_gap_s, is an InputError naming the scan.
#include <Eigen/Geometry>
#include <quasiloc/core/trajectory_io.h>
#include <string>
#include <vector>

namespace quasiloc::map
{
enum class TrajectoryFormat
{
    Tum,
    Kitti,
    Bag  ///< ScanPoseOptions::poses, read from a bag by the caller
};

enum class ScanTimeSource
{
    FileNames,  ///< the scan file's stem as a number
    TimesFile,  ///< one time per line, in scan order
    Order,      ///< the scan's index
    Stamps,     ///< the scans' own stamps (a bag's message headers), given to ScanPoses
    Auto        ///< an option's value only: FileNames for files, Stamps for a bag (resolved before ScanPoses)
};

struct ScanPoseOptions
{
    std::string trajectory;
    TrajectoryFormat format = TrajectoryFormat::Tum;
    ScanTimeSource times = ScanTimeSource::FileNames;
    std::string times_file;
    double time_scale = 1.0;      ///< seconds per unit of the names' / times file's numbers (TUM)
    double frame_period_s = 0.1;  ///< KITTI poses: time between lines
    double max_pose_gap_s = 0.5;  ///< TUM: longest interval between two poses a time may fall into
    Eigen::Isometry3d T_body_lidar = Eigen::Isometry3d::Identity();
    core::Trajectory poses;  ///< TrajectoryFormat::Bag: T_world_body; `trajectory` names where it came from
};

/** A 3x4 (or 4x4) row-major matrix on the line "<key>: v0 v1 ..." of a KITTI-style calibration file. InputError
 *  naming the file for a missing file, key or a malformed matrix. */
Eigen::Isometry3d readCalibrationMatrix(const std::string& path, const std::string& key);

/** KITTI poses: one 3x4 row-major matrix per line ('#' comments, blank lines skipped). */
std::vector<Eigen::Isometry3d> readKittiPoses(const std::string& path);

/** One number per line ('#' comments, blank lines skipped). */
std::vector<double> readScanTimes(const std::string& path);

/** The number a file name's stem spells ("0000000042.bin" -> 42, "1626343512.123.pcd" -> 1626343512.123);
 *  InputError naming the file when it spells none. */
double numberFromFileName(const std::string& path);

class ScanPoses
{
   public:
    /** Reads the trajectory and times for the scans `scan_names` (`stamps`: their own times in seconds, for
     *  ScanTimeSource::Stamps); InputError naming the file (trajectory, times file or scan) when a scan's time has no
     *  pose. */
    ScanPoses(const ScanPoseOptions& options, const std::vector<std::string>& scan_names,
              const std::vector<double>& stamps = {});

    size_t size() const { return stamps_.size(); }
    /** Scan i's time, seconds. */
    double stamp(size_t i) const { return stamps_[i]; }
    /** Is stamp(i) + dt_s within the trajectory (and not in too long a gap)? */
    bool covers(size_t i, double dt_s) const;
    /** T_world_lidar at stamp(i) + dt_s; InputError naming scan i when not covered. */
    Eigen::Isometry3d T_world_lidar(size_t i, double dt_s = 0) const;

   private:
    bool interpolate(double t, Eigen::Isometry3d& T_world_body) const;

    ScanPoseOptions options_;
    std::vector<std::string> names_;
    std::vector<double> stamps_;
    core::Trajectory trajectory_;  ///< T_world_body, time-sorted
    double max_gap_s_ = 0;
};

}  // namespace quasiloc::map
