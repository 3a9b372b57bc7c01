// Fuzz target: map-build's trajectory and scan-time files (scan_poses.h): KITTI poses, scan-times lists, a KITTI-style
// calibration line, and a TUM trajectory looked up at scan times taken from file names.
#include <quasiloc/map/scan_poses.h>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    using namespace quasiloc;
    const std::string path = fuzz::writeInput(data, size, "poses.txt");
    fuzz::expectCleanError([&] { (void)map::readKittiPoses(path); });
    fuzz::expectCleanError([&] { (void)map::readScanTimes(path); });
    fuzz::expectCleanError([&] { (void)map::readCalibrationMatrix(path, "T_cam2rect_velo"); });
    fuzz::expectCleanError([&] {
        map::ScanPoseOptions o;
        o.trajectory = path;
        const map::ScanPoses poses(o, {"/scans/0.05.pcd", "/scans/1.pcd"});
        (void)poses.T_world_lidar(1, 0.05);
    });
    fuzz::expectCleanError([&] {
        map::ScanPoseOptions o;
        o.trajectory = path;
        o.format = map::TrajectoryFormat::Kitti;
        (void)map::ScanPoses(o, {"/scans/0000000000.bin", "/scans/0000000002.bin"});
    });
    return 0;
}
