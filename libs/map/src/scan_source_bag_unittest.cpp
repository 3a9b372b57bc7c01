// What map-build needs from libs/map for bag scans: scan poses at given stamps and from given poses (scan_poses.h),
// the [MapBuild] rules of source = bag, and passes that read a source front to back (ScanSource::forEach).
#include <gtest/gtest.h>

#include <quasiloc/core/pose.h>
#include <quasiloc/map/map_build.h>

#include "test_cloud_files.h"

using namespace quasiloc;
using namespace quasiloc::map;
using namespace quasiloc::map::test;

namespace
{
/** Scans that can only be read front to back (as a bag's): read(i) is refused. */
class SequentialSource : public ScanSource
{
   public:
    std::vector<LidarScan> scans;
    size_t size() const override { return scans.size(); }
    std::string name(size_t i) const override { return scans[i].name; }
    LidarScan read(size_t) const override { throw std::logic_error("read(i) on a sequential source"); }
    void forEach(const std::function<void(size_t, LidarScan&&)>& visit) const override
    {
        ++passes;
        for (size_t i = 0; i < scans.size(); ++i) visit(i, LidarScan(scans[i]));
    }
    mutable int passes = 0;
};

core::Trajectory straightLine(double t0)
{
    core::Trajectory t;
    for (int k = 0; k < 3; ++k) t.poses.push_back({t0 + k, mrpt::poses::CPose3D(double(k), 0, 0, 0, 0, 0)});
    return t;
}
}  // namespace

TEST(ScanPoses, StampsAndPosesGivenByTheCaller)
{
    ScanPoseOptions o;
    o.format = TrajectoryFormat::Bag;
    o.trajectory = "run.bag topic /odom";
    o.times = ScanTimeSource::Stamps;
    o.poses = straightLine(1317000000.0);
    o.max_pose_gap_s = 1.5;
    std::swap(o.poses.poses[0], o.poses.poses[2]);  // out of order: sorted
    const ScanPoses poses(o, {"m0", "m1"}, {1317000000.5, 1317000002.0});
    EXPECT_NEAR(poses.T_world_lidar(0).translation().x(), 0.5, 1e-6);
    EXPECT_NEAR(poses.T_world_lidar(1).translation().x(), 2.0, 1e-12);
    expectInputError([&] { ScanPoses(o, {"m0"}, {1317000003.0}); }, "m0", "has no pose in run.bag topic /odom");
    o.format = TrajectoryFormat::Kitti;
    expectInputError([&] { ScanPoses(o, {"m0"}, {1.0}); }, "run.bag", "KITTI poses are numbered by frame");
    o.times = ScanTimeSource::Auto;
    expectInputError([&] { ScanPoses(o, {"m0"}, {1.0}); }, "ScanPoses", "auto must be resolved");
}

TEST(MapBuildOptions, BagSourceRules)
{
    MapBuildOptions o;
    o.output = "/tmp/m.map";
    o.source = ScanSourceKind::Bag;
    o.trajectory = "t.tum";
    expectInputError([&] { o.check("c.ini"); }, "[MapBuild] bag", "is required with source = bag");
    o.bag = "run.bag";
    o.check("c.ini");
    EXPECT_EQ(o.poseOptions().times, ScanTimeSource::Stamps);  // auto: a bag's stamps
    o.scan_times = ScanTimeSource::FileNames;
    expectInputError([&] { o.check("c.ini"); }, "[MapBuild] scan_times", "bag scans have no file names");
    o.scan_times = ScanTimeSource::Auto;
    o.trajectory_format = TrajectoryFormat::Bag;
    o.trajectory.clear();
    expectInputError([&] { o.check("c.ini"); }, "[MapBuild] bag_pose_topic", "is required");
    o.bag_pose_topic = "/odom";
    o.check("c.ini");  // the poses come from the scans' bag
    EXPECT_EQ(o.trajectoryBag(), "run.bag");
    EXPECT_EQ(o.poseOptions().trajectory, "run.bag topic /odom");
    o.source = ScanSourceKind::Folder;
    expectInputError([&] { o.check("c.ini"); }, "[MapBuild] scan_folder", "for scans from a bag set source = bag");
    o.scan_folder = "scans";
    o.check("c.ini");  // files with the poses of `bag`
    o.bag.clear();
    expectInputError([&] { o.check("c.ini"); }, "[MapBuild] trajectory", "the bag of the poses");
    o.trajectory = "poses.bag";
    o.check("c.ini");
    EXPECT_EQ(o.poseOptions().times, ScanTimeSource::FileNames);  // auto: file names
    o.scan_times = ScanTimeSource::Stamps;
    expectInputError([&] { o.check("c.ini"); }, "[MapBuild] scan_times", "only bag scans carry stamps");
}

TEST(MapBuild, PassesReadASequentialSourceFrontToBack)
{
    SequentialSource source;
    for (int s = 0; s < 2; ++s)
    {
        LidarScan scan;
        scan.name = "bag topic /points message " + std::to_string(s);
        for (int k = 0; k < 4; ++k)
        {
            scan.points.emplace_back(5.f + 0.01f * float(k), 2.f * float(k), 0.f);
            scan.intensity.push_back(100.f);
        }
        scan.invalid_points = 3;
        source.scans.push_back(scan);
    }
    MapBuildOptions o;
    o.source = ScanSourceKind::Bag;
    o.bag = "bag";
    ScanPoseOptions po = o.poseOptions();
    po.format = TrajectoryFormat::Bag;
    po.poses = straightLine(10.0);
    const ScanPoses poses(po, {source.name(0), source.name(1)}, {10.0, 10.0});
    const MapBuildResult r = buildMap(o, source, poses);  // carving and range_ring: three passes
    EXPECT_EQ(source.passes, 3);
    EXPECT_EQ(r.map.size() + r.removed.size(), 4u);
    EXPECT_EQ(r.points_read, 8u);
    EXPECT_EQ(r.points_invalid, 6u);
}
