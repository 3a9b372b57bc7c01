// map-build's bag source: scans and poses written with BagWriter (ROS 2 MCAP, and ROS 1 where this build has it) come
// back from BagScanSource / readBagTrajectory; a missing topic, a topic of another type and a truncated message are
// errors naming the bag, the topic and the message index.
#include <gtest/gtest.h>

#include <cstdlib>
#include <quasiloc/core/error.h>
#include <quasiloc/ros/bag_scan_source.h>
#include <quasiloc/ros/bag_writer.h>

#include "rosbag2_test_helpers.h"

namespace quasiloc::ros
{
namespace
{
using dataset::BagFormat;

constexpr std::int64_t kT0 = 1317000000000000000;  // ns

/** Scan k: k + 1 points at (k, j, 1), intensity j; x y z intensity float32. */
PointCloud2Msg scan(int k)
{
    PointCloud2Msg m;
    m.header = {kT0 + std::int64_t(k) * 100000000, "velodyne"};
    using F = PointFieldMsg;
    m.fields = {{"x", 0, F::kFloat32, 1},
                {"y", 4, F::kFloat32, 1},
                {"z", 8, F::kFloat32, 1},
                {"intensity", 12, F::kFloat32, 1}};
    m.height = 1;
    m.width = std::uint32_t(k + 1);
    m.point_step = 16;
    m.row_step = 16 * m.width;
    for (int j = 0; j <= k; ++j)
        for (float v : {float(k), float(j), 1.f, float(j)})
        {
            const auto* b = reinterpret_cast<const std::uint8_t*>(&v);
            m.data.insert(m.data.end(), b, b + 4);
        }
    return m;
}

PoseMsg pose(int k)
{
    PoseMsg p;
    p.header = {kT0 + std::int64_t(k) * 50000000, "map"};
    p.position = {0.5 * k, 0, 0};
    p.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * k, Eigen::Vector3d::UnitZ()));
    return p;
}

/** A bag of 4 scans on /points (message `truncated` cut short), 7 poses on /odom. */
std::string writeBag(const std::string& dir, BagFormat format, int truncated = -1)
{
    const std::string path = dir + (format == BagFormat::Ros1 ? "/run.bag" : "/run_mcap");
    BagWriter w(path, format);
    for (int k = 0; k < 4; ++k)
    {
        PointCloud2Msg m = scan(k);
        if (k == truncated) m.data.resize(m.data.size() - 4);
        w.pointCloud2("/points", m);
    }
    for (int k = 0; k < 7; ++k) w.pose("/odom", pose(k));
    w.close();
    return path;
}

std::vector<BagFormat> formats()
{
    std::vector<BagFormat> f = {BagFormat::Mcap};
    if (haveRos1()) f.push_back(BagFormat::Ros1);
    return f;
}
}  // namespace

TEST(BagScanSource, ScansComeBackWithTheirStampsInOnePassOrOneByOne)
{
    for (BagFormat format : formats())
    {
        test::TempDir dir;
        const std::string bag = writeBag(dir.path, format);
        const BagScanSource source(bag, "");  // the only PointCloud2 topic
        EXPECT_EQ(source.topic(), "/points");
        ASSERT_EQ(source.size(), 4u);
        EXPECT_EQ(source.name(2), bag + " topic /points message 2");
        const std::vector<double> stamps = source.stampsSeconds();
        EXPECT_EQ(stamps[3], 1317000000.3);  // the double nearest the decimal time
        size_t visited = 0;
        source.forEach([&](size_t i, map::LidarScan&& s) {
            EXPECT_EQ(i, visited++);
            ASSERT_EQ(s.size(), i + 1);
            EXPECT_EQ(s.name, source.name(i));
            EXPECT_EQ(s.points.back(), Eigen::Vector3f(float(i), float(i), 1.f));
            EXPECT_EQ(s.intensity.back(), float(i));
        });
        EXPECT_EQ(visited, 4u);
        EXPECT_EQ(source.read(2).points, source.read(2).points);
        EXPECT_EQ(source.read(2).size(), 3u);
    }
}

TEST(BagScanSource, TrajectoryFromAPoseTopic)
{
    for (BagFormat format : formats())
    {
        test::TempDir dir;
        const core::Trajectory t = readBagTrajectory(writeBag(dir.path, format), "/odom");
        ASSERT_EQ(t.poses.size(), 7u);
        EXPECT_EQ(t.poses[6].t, 1317000000.3);
        EXPECT_NEAR(t.poses[6].pose.x(), 3.0, 1e-12);
        EXPECT_NEAR(t.poses[6].pose.yaw(), 0.6, 1e-12);
    }
}

TEST(BagScanSource, MissingTopicOtherTypeAndTruncatedMessageAreErrors)
{
    for (BagFormat format : formats())
    {
        test::TempDir dir;
        const std::string bag = writeBag(dir.path, format, /*truncated=*/2);
        std::string e = test::errorOf([&] { BagScanSource(bag, "/velodyne_points"); });
        EXPECT_NE(e.find(bag + ": has no topic /velodyne_points (its sensor_msgs/PointCloud2 topics: /points)"),
                  std::string::npos)
            << e;
        e = test::errorOf([&] { BagScanSource(bag, "/odom"); });
        EXPECT_NE(e.find(bag + ": topic /odom holds geometry_msgs/PoseStamped messages, not sensor_msgs/PointCloud2"),
                  std::string::npos)
            << e;
        e = test::errorOf([&] { BagScanSource(bag, "/points"); });
        EXPECT_NE(e.find(bag + " topic /points message 2: truncated point data: 44 bytes, 1 row of 3 points"),
                  std::string::npos)
            << e;
        e = test::errorOf([&] { readBagTrajectory(bag, "/points"); });
        EXPECT_NE(e.find("topic /points holds sensor_msgs/PointCloud2 messages, not geometry_msgs/PoseStamped or "
                         "nav_msgs/Odometry or geometry_msgs/TransformStamped"),
                  std::string::npos)
            << e;
    }
}

TEST(BagScanSource, UnsetStampIsAnErrorOnlyWhenStampsAreUsed)
{
    test::TempDir dir;
    const std::string path = dir.path + "/unset";
    BagWriter w(path, BagFormat::Mcap);
    PointCloud2Msg m = scan(1);
    m.header.stamp_ns = 0;
    w.pointCloud2("/points", m);
    w.pointCloud2("/points", scan(1));
    w.close();
    const BagScanSource source(path, "/points");
    EXPECT_EQ(source.size(), 2u);
    const std::string e = test::errorOf([&] { source.stampsSeconds(); });
    EXPECT_NE(e.find(path + " topic /points message 0: its header stamp is unset (0)"), std::string::npos) << e;
}

TEST(BagScanSource, SecondsFromNanosecondsAreCorrectlyRounded)
{
    for (std::int64_t ns : {std::int64_t(1317000000100000000), std::int64_t(1700000000333333333), std::int64_t(1),
                            std::int64_t(-1500000000), std::int64_t(999999999)})
    {
        char text[64];
        std::snprintf(text, sizeof text, "%s%lld.%09lld", ns < 0 ? "-" : "", std::llabs(ns) / 1000000000LL,
                      std::llabs(ns) % 1000000000LL);
        EXPECT_EQ(secondsFromNs(ns), std::strtod(text, nullptr)) << text;
    }
    EXPECT_EQ(secondsFromNs(1317000000100000000), 1317000000.1);
}

TEST(BagScanSource, BagsWrittenByAnotherLibrary)
{
    // rosbags (Python) wrote these SQLite3 and MCAP bags; their PointCloud2 has x y z only: no intensity to map.
    QUASILOC_REQUIRE_ROS2_DATA();
    for (const std::string bag :
         {"rosbags_rs_all_types_sqlite3/test_bag_sqlite3.db3", "rosbags_rs_all_types_mcap/test_bag_mcap.mcap"})
    {
        const std::string path = test::ros2Data(bag);
        std::string e = test::errorOf([&] { BagScanSource(path, ""); });
        EXPECT_NE(e.find(path + " topic /test/sensor_msgs/point_cloud2 message 0: no intensity field"),
                  std::string::npos)
            << e;
        e = test::errorOf([&] { BagScanSource(path, "/test/sensor_msgs/imu"); });
        EXPECT_NE(e.find("topic /test/sensor_msgs/imu holds sensor_msgs/Imu messages, not sensor_msgs/PointCloud2"),
                  std::string::npos)
            << e;
        const core::Trajectory t = readBagTrajectory(path, "/test/nav_msgs/odometry");
        EXPECT_EQ(t.poses.size(), 2u);
    }
}

}  // namespace quasiloc::ros
