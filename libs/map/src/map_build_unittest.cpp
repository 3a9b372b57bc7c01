// Scan poses (trajectory formats, scan times, coverage errors) and the whole map build on an in-memory source.
#include <gtest/gtest.h>

#include <fstream>
#include <quasiloc/map/map_build.h>

#include "test_cloud_files.h"

using namespace quasiloc::map;
using namespace quasiloc::map::test;

namespace
{
void writeText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

std::string kittiLine(double x) { return "1 0 0 " + std::to_string(x) + " 0 1 0 0 0 0 1 0\n"; }

/** Scans held in memory, one per name. */
class MemorySource : public ScanSource
{
   public:
    std::vector<LidarScan> scans;
    size_t size() const override { return scans.size(); }
    std::string name(size_t i) const override { return scans[i].name; }
    LidarScan read(size_t i) const override { return scans[i]; }
};
}  // namespace

TEST(ScanPoses, KittiPosesByFileNumber)
{
    TempDir dir;
    writeText(dir.file("poses.txt"), "# T_world_body\n" + kittiLine(0) + kittiLine(1) + kittiLine(2) + kittiLine(3));
    ScanPoseOptions o;
    o.trajectory = dir.file("poses.txt");
    o.format = TrajectoryFormat::Kitti;
    o.T_body_lidar.translation() = Eigen::Vector3d(0, 0, 2);
    const ScanPoses poses(o, {"/d/0000000000.bin", "/d/0000000002.bin"});
    EXPECT_NEAR(poses.T_world_lidar(1).translation().x(), 2.0, 1e-12);
    EXPECT_NEAR(poses.T_world_lidar(1).translation().z(), 2.0, 1e-12);
    // Half a frame later: half way to the next pose (per-point deskewing).
    EXPECT_NEAR(poses.T_world_lidar(1, 0.05).translation().x(), 2.5, 1e-9);
    expectInputError(
        [&] {
            ScanPoses(o, {"/d/0000000000.bin", "/d/0000000004.bin"});
        },
        "0000000004.bin", "needs pose line 5");
    o.times = ScanTimeSource::Order;
    const ScanPoses by_order(o, {"a.bin", "b.bin", "c.bin"});
    EXPECT_NEAR(by_order.T_world_lidar(2).translation().x(), 2.0, 1e-12);
}

TEST(ScanPoses, TumCoverageAndGaps)
{
    TempDir dir;
    writeText(dir.file("traj.tum"), "10 0 0 0 0 0 0 1\n10.1 1 0 0 0 0 0 1\n12 2 0 0 0 0 0 1\n");
    writeText(dir.file("times.txt"), "10.05\n11.0\n");
    ScanPoseOptions o;
    o.trajectory = dir.file("traj.tum");
    const ScanPoses ok(o, {dir.file("10.05.pcd")});
    EXPECT_NEAR(ok.T_world_lidar(0).translation().x(), 0.5, 1e-9);
    expectInputError([&] { ScanPoses(o, {dir.file("9.5.pcd")}); }, "9.5.pcd", "has no pose");
    // 11.0 lies in a 1.9 s gap between poses: no pose with max_pose_gap_s = 0.5.
    o.times = ScanTimeSource::TimesFile;
    o.times_file = dir.file("times.txt");
    expectInputError([&] { ScanPoses(o, {"a.pcd", "b.pcd"}); }, "b.pcd", "has no pose");
    expectInputError([&] { ScanPoses(o, {"a.pcd"}); }, "times.txt", "lists 2 times for 1 scans");
    o.times = ScanTimeSource::FileNames;
    expectInputError([&] { ScanPoses(o, {"scan_a.pcd"}); }, "scan_a.pcd", "does not spell a number");
}

TEST(ScanPoses, CalibrationMatrix)
{
    TempDir dir;
    writeText(dir.file("calib.txt"), "P2: 1 2 3\nT_cam_velo: 0 -1 0 1 0 0 -1 2 1 0 0 3\n");
    const Eigen::Isometry3d T = readCalibrationMatrix(dir.file("calib.txt"), "T_cam_velo");
    EXPECT_NEAR(T.translation().z(), 3.0, 1e-12);
    EXPECT_NEAR(T.linear()(0, 1), -1.0, 1e-12);
    expectInputError([&] { readCalibrationMatrix(dir.file("calib.txt"), "Tr"); }, "calib.txt", "no line 'Tr: ...'");
    expectInputError([&] { readCalibrationMatrix(dir.file("calib.txt"), "P2"); }, "calib.txt", "expected a 3x4");
}

TEST(MapBuild, FusesVoxelsAndNormalisesIntensity)
{
    // Two scans of the same four points 5 m away, raw intensities 100 and 200 (8-bit: divided by 255).
    TempDir dir;
    writeText(dir.file("traj.tum"), "0 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n");
    MemorySource source;
    for (int s = 0; s < 2; ++s)
    {
        LidarScan scan;
        scan.name = dir.file(std::to_string(s) + ".pcd");
        for (int k = 0; k < 4; ++k)
        {
            scan.points.emplace_back(5.f + 0.01f * float(k), 2.f * float(k), 0.f);
            scan.intensity.push_back(s == 0 ? 100.f : 200.f);
        }
        source.scans.push_back(scan);
    }
    MapBuildOptions o;
    o.trajectory = dir.file("traj.tum");
    o.reflectivity_normalisation = ReflectivityNormalisation::None;
    o.carve = false;
    const ScanPoses poses(o.poseOptions(), {source.name(0), source.name(1)});
    const MapBuildResult r = buildMap(o, source, poses);
    ASSERT_EQ(r.map.size(), 4u);
    EXPECT_NEAR(r.map.reflectivity(0), 150.0 / 255.0, 1e-5);
    EXPECT_EQ(r.points_read, 8u);
}

TEST(MapBuild, RingsFromAzimuthWraps)
{
    std::vector<Eigen::Vector3f> pts;
    for (int ring = 0; ring < 3; ++ring)
        for (int k = 0; k < 36; ++k)
        {
            const float az = float(-M_PI + (k + 0.5) * 2 * M_PI / 36);
            pts.emplace_back(std::cos(az), std::sin(az), 0.f);
        }
    const std::vector<uint16_t> ring = ringsFromAzimuthWraps(pts);
    EXPECT_EQ(ring.front(), 0);
    EXPECT_EQ(ring[36], 1);
    EXPECT_EQ(ring.back(), 2);
}

TEST(MapBuild, PerPointTimeAndRingFields)
{
    TempDir dir;
    writeText(dir.file("ouster.pcd"),
              "VERSION 0.7\nFIELDS x y z intensity t ring\nSIZE 4 4 4 4 4 2\nTYPE F F F F U U\nCOUNT 1 1 1 1 1 1\n"
              "WIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n1 0 0 10 0 3\n2 0 0 20 50000000 4\n");
    RawCloud pcd = readCloud(dir.file("ouster.pcd"));
    EXPECT_EQ(pcd.time_field, "t");
    EXPECT_EQ(pcd.ring_field, "ring");
    const LidarScan scan = scanFromCloud(std::move(pcd), "ouster.pcd");
    ASSERT_EQ(scan.time_s.size(), 2u);
    EXPECT_NEAR(scan.time_s[1], 0.05, 1e-12);  // ns -> s
    EXPECT_FALSE(scan.time_absolute);
    ASSERT_EQ(scan.ring.size(), 2u);
    EXPECT_EQ(scan.ring[1], 4);
    writeText(dir.file("velodyne.ply"),
              "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
              "property float intensity\nproperty uint16 ring\nproperty float time\nend_header\n1 2 3 4 7 -0.02\n");
    const RawCloud ply = readCloud(dir.file("velodyne.ply"));
    ASSERT_EQ(ply.time.size(), 1u);
    EXPECT_NEAR(ply.time[0], -0.02, 1e-7);
    EXPECT_EQ(ply.ring[0], 7);
    // A cloud without such fields has none (KITTI .bin never has).
    writeText(dir.file("plain.pcd"),
              "VERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\n"
              "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3 4\n");
    EXPECT_TRUE(readCloud(dir.file("plain.pcd")).time.empty());
}

TEST(MapBuild, DeskewMovesEachPointWithItsOwnPose)
{
    // The LiDAR drives along x at 10 m/s; a wall stands at world x = 20. Points measured at 0 .. 0.1 s after the
    // stamp see it ever nearer (20 - 10 t in the LiDAR frame): deskewed, all land on x = 20; not deskewed, they
    // spread over 1 m.
    TempDir dir;
    writeText(dir.file("traj.tum"), "0 0 0 0 0 0 0 1\n1 10 0 0 0 0 0 1\n");
    ScanPoseOptions po;
    po.trajectory = dir.file("traj.tum");
    po.times = ScanTimeSource::Order;
    po.max_pose_gap_s = 2;
    const ScanPoses poses(po, {"scan"});
    LidarScan scan;
    scan.name = "scan";
    for (int k = 0; k <= 100; ++k)
    {
        const double t = 0.001 * k;
        scan.points.emplace_back(float(20 - 10 * t), float(k % 7), 0.f);
        scan.intensity.push_back(1.f);
        scan.time_s.push_back(t);
    }
    ScanFilter filter;
    const WorldScan skewed =
        toWorld(LidarScan(scan), poses, 0, ScanFilter{filter.min_range_m, filter.max_range_m, false});
    const WorldScan deskewed = toWorld(LidarScan(scan), poses, 0, filter);
    ASSERT_TRUE(deskewed.deskewed);
    ASSERT_FALSE(skewed.deskewed);
    double max_err = 0, max_skew = 0;
    for (size_t k = 0; k < deskewed.size(); ++k)
    {
        max_err = std::max(max_err, std::abs(double(deskewed.points[k].x()) - 20.0));
        max_skew = std::max(max_skew, std::abs(double(skewed.points[k].x()) - 20.0));
    }
    EXPECT_LT(max_err, 0.005);  // within one deskew step (0.1 s / 256 at 10 m/s = 4 mm)
    EXPECT_GT(max_skew, 0.9);
}
