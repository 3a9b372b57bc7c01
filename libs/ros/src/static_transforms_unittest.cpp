// The static transforms tree (static_transforms.h) and the LiDAR extrinsic from a bag's /tf_static
// (readBagExtrinsic): links chained in either direction over several hops, checked against the transforms composed
// by hand; a frame in no link, frames not connected and a cycle are errors naming the topic and the frames; the
// TFMessages come back from ROS 1 and MCAP bags written here and from the SQLite3 and MCAP bags rosbags wrote.
#include <gtest/gtest.h>

#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/ros/bag_scan_source.h>
#include <quasiloc/ros/bag_writer.h>
#include <quasiloc/ros/static_transforms.h>

#include "rosbag2_test_helpers.h"

namespace quasiloc::ros
{
namespace
{
using dataset::BagFormat;

TransformMsg link(const std::string& parent, const std::string& child, const Eigen::Isometry3d& T_parent_child)
{
    TransformMsg t;
    t.header = {1317000000000000000, parent};
    t.child_frame_id = child;
    t.translation = T_parent_child.translation();
    t.rotation = Eigen::Quaterniond(T_parent_child.rotation());
    return t;
}

Eigen::Isometry3d transform(double x, double y, double z, double angle, const Eigen::Vector3d& axis)
{
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(x, y, z);
    return T;
}

void expectNear(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b)
{
    EXPECT_LT((a.matrix() - b.matrix()).cwiseAbs().maxCoeff(), 1e-12) << a.matrix() << "\nvs\n" << b.matrix();
}

// A FAST-LIO-like tree: base_link -> imu_link -> velodyne, base_link -> camera.
const Eigen::Isometry3d T_base_imu = transform(0.1, -0.2, 0.3, 0.4, {1, 2, 3});
const Eigen::Isometry3d T_imu_lidar = transform(-0.011, -0.0234, 0.044, 2.5, {0, 0, 1});
const Eigen::Isometry3d T_base_camera = transform(0.5, 0, 0.2, -1.2, {3, -1, 0.5});

StaticTransforms tree()
{
    StaticTransforms tf;
    tf.add(link("base_link", "imu_link", T_base_imu));
    tf.add(link("imu_link", "velodyne", T_imu_lidar));
    tf.add(link("base_link", "camera", T_base_camera));
    return tf;
}
}  // namespace

TEST(StaticTransforms, LinksChainInEitherDirectionOverSeveralHops)
{
    const StaticTransforms tf = tree();
    expectNear(core::toIsometry(tf.chain("imu_link", "velodyne", "tf")), T_imu_lidar);
    expectNear(core::toIsometry(tf.chain("velodyne", "imu_link", "tf")), T_imu_lidar.inverse());
    expectNear(core::toIsometry(tf.chain("base_link", "velodyne", "tf")), T_base_imu * T_imu_lidar);
    expectNear(core::toIsometry(tf.chain("camera", "velodyne", "tf")),
               T_base_camera.inverse() * T_base_imu * T_imu_lidar);
    expectNear(core::toIsometry(tf.chain("velodyne", "camera", "tf")),
               T_imu_lidar.inverse() * T_base_imu.inverse() * T_base_camera);
    expectNear(core::toIsometry(tf.chain("velodyne", "velodyne", "tf")), Eigen::Isometry3d::Identity());
    EXPECT_EQ(tf.describeChain("camera", "velodyne"), "camera <- base_link -> imu_link -> velodyne");
    EXPECT_EQ(tf.describeChain("velodyne", "base_link"), "velodyne <- imu_link <- base_link");
}

TEST(StaticTransforms, AFrameGivenAgainTakesItsLatestParentAndTransform)
{
    StaticTransforms tf = tree();
    const Eigen::Isometry3d T_camera_lidar = transform(1, 2, 3, 0.3, {0, 1, 0});
    tf.add(link("camera", "velodyne", T_camera_lidar));
    expectNear(core::toIsometry(tf.chain("camera", "velodyne", "tf")), T_camera_lidar);
    expectNear(core::toIsometry(tf.chain("base_link", "velodyne", "tf")), T_base_camera * T_camera_lidar);
    EXPECT_EQ(tf.describe(), "base_link -> imu_link, camera -> velodyne, base_link -> camera");
}

TEST(StaticTransforms, AMissingLinkAnUnknownFrameAndACycleAreErrorsNamingTheFrames)
{
    StaticTransforms tf = tree();
    tf.add(link("odom", "gps", Eigen::Isometry3d::Identity()));
    EXPECT_FALSE(tf.lookup("gps", "velodyne").has_value());
    std::string e = test::errorOf([&] { tf.chain("gps", "velodyne", "run.bag topic /tf_static"); });
    EXPECT_NE(e.find("run.bag topic /tf_static: no chain of static transforms from 'gps' to 'velodyne' (transforms "
                     "there, parent -> child: base_link -> imu_link, imu_link -> velodyne, base_link -> camera, "
                     "odom -> gps)"),
              std::string::npos)
        << e;
    e = test::errorOf([&] { tf.chain("body", "velodyne", "run.bag topic /tf_static"); });
    EXPECT_NE(e.find("run.bag topic /tf_static: frame 'body' is in no static transform"), std::string::npos) << e;

    StaticTransforms cycle = tree();
    cycle.add(link("velodyne", "base_link", Eigen::Isometry3d::Identity()));
    EXPECT_FALSE(cycle.lookup("camera", "imu_link").has_value());
    e = test::errorOf([&] { cycle.chain("camera", "imu_link", "tf"); });
    EXPECT_NE(e.find("the parents of frame 'camera' lead back to a frame passed before: a cycle"), std::string::npos)
        << e;
    StaticTransforms self;
    self.add(link("a", "a", Eigen::Isometry3d::Identity()));
    self.add(link("a", "b", Eigen::Isometry3d::Identity()));
    e = test::errorOf([&] { self.chain("b", "a", "tf"); });
    EXPECT_NE(e.find("the parents of frame 'b' lead back to a frame passed before: a cycle"), std::string::npos) << e;
}

TEST(StaticTransforms, TheLidarExtrinsicComesFromTheTfStaticOfRos1AndMcapBags)
{
    std::vector<BagFormat> formats = {BagFormat::Mcap};
    if (haveRos1()) formats.push_back(BagFormat::Ros1);
    for (BagFormat format : formats)
    {
        const test::TempDir dir;
        const std::string path = dir.path + (format == BagFormat::Ros1 ? "/tf.bag" : "/tf_mcap");
        {
            BagWriter w(path, format);
            // Two TFMessages, as tf2's static broadcasters latch one each.
            w.tfStatic("/tf_static", {link("base_link", "imu_link", T_base_imu)});
            w.tfStatic("/tf_static",
                       {link("imu_link", "velodyne", T_imu_lidar), link("base_link", "camera", T_base_camera)});
            w.close();
        }
        const BagExtrinsic e = readBagExtrinsic(path, "/tf_static", "camera", "velodyne", "/points");
        // The quaternions round-trip through the bag: equal to ~1e-16.
        expectNear(e.T_body_lidar, T_base_camera.inverse() * T_base_imu * T_imu_lidar);
        EXPECT_EQ(e.chain, "camera <- base_link -> imu_link -> velodyne");

        std::string err = test::errorOf([&] { readBagExtrinsic(path, "/tf_static", "body", "velodyne", "/points"); });
        EXPECT_NE(err.find(path + " topic /tf_static: frame 'body' is in no static transform (transforms there, parent "
                                  "-> child: base_link -> imu_link, imu_link -> velodyne, base_link -> camera) "
                                  "(T_body_lidar from body_frame 'body' to the LiDAR frame 'velodyne', the "
                                  "header.frame_id of /points)"),
                  std::string::npos)
            << err;
        err = test::errorOf([&] { readBagExtrinsic(path, "/tf", "camera", "velodyne", "/points"); });
        EXPECT_NE(err.find(path + ": has no topic /tf (its tf2_msgs/TFMessage topics: /tf_static)"), std::string::npos)
            << err;
    }
}

TEST(StaticTransforms, TFMessagesOfBagsWrittenByAnotherLibrary)
{
    // rosbags (Python) wrote the same messages into SQLite3 and MCAP storage.
    QUASILOC_REQUIRE_ROS2_DATA();
    std::vector<std::string> described;
    for (const std::string bag :
         {"rosbags_rs_all_types_sqlite3/test_bag_sqlite3.db3", "rosbags_rs_all_types_mcap/test_bag_mcap.mcap"})
    {
        const auto source = openMessageSource(test::ros2Data(bag));
        const StaticTransforms tf = readStaticTransforms(*source, "/test/tf2_msgs/tf_message");
        EXPECT_FALSE(tf.empty());
        described.push_back(tf.describe());
        const std::string e = test::errorOf([&] { readStaticTransforms(*source, "/test/sensor_msgs/imu"); });
        EXPECT_NE(e.find("topic /test/sensor_msgs/imu holds sensor_msgs/Imu messages, not tf2_msgs/TFMessage"),
                  std::string::npos)
            << e;
    }
    EXPECT_EQ(described[0], "test_frame -> child_frame");
    EXPECT_EQ(described[1], described[0]);
}

TEST(StaticTransforms, TheLidarFrameIsTheFrameIdOfEveryScan)
{
    const test::TempDir dir;
    const std::string path = dir.path + "/frames_mcap";
    {
        BagWriter w(path, BagFormat::Mcap);
        for (int k = 0; k < 3; ++k)
        {
            PointCloud2Msg m;
            m.header = {1317000000000000000 + k, k == 2 ? "os_sensor" : "velodyne"};
            m.fields = {{"x", 0, PointFieldMsg::kFloat32, 1},
                        {"y", 4, PointFieldMsg::kFloat32, 1},
                        {"z", 8, PointFieldMsg::kFloat32, 1},
                        {"intensity", 12, PointFieldMsg::kFloat32, 1}};
            m.height = m.width = 1;
            m.point_step = m.row_step = 16;
            m.data.assign(16, 0);
            w.pointCloud2(k == 2 ? "/mixed" : "/points", m);
            if (k == 2)
                w.pointCloud2("/mixed", [&] {
                    PointCloud2Msg first = m;
                    first.header.frame_id = "velodyne";
                    return first;
                }());
        }
        w.close();
    }
    EXPECT_EQ(BagScanSource(path, "/points").lidarFrame(), "velodyne");
    const std::string e = test::errorOf([&] { BagScanSource(path, "/mixed").lidarFrame(); });
    EXPECT_NE(e.find(path + " topic /mixed message 1: has header.frame_id 'velodyne' where message 0 has 'os_sensor': "
                            "the scans of one topic must share one LiDAR frame"),
              std::string::npos)
        << e;
}

}  // namespace quasiloc::ros
