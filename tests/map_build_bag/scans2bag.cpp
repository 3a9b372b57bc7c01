// scans2bag: a folder of scans (KITTI .bin, PCD, PLY) as sensor_msgs/PointCloud2 messages in a ROS 1 bag or a rosbag2
// MCAP folder, for map-build's bag tests (tests/e2e/map_build_bag*.sh). Each scan is stamped by its line of a times
// file (decimal seconds, exact to the nanosecond); a TUM trajectory can go into the same bag as PoseStamped messages.
// Layouts: xyzi32 (x y z intensity float32, one row, as a Velodyne driver's minimal cloud), organised64 (x y z
// intensity float64 in two rows padded with NaN points and row padding: the same valid points in the same order),
// no_xyz (the fields named a b c: a bad message). --truncate K cuts message K's data short. The clouds' frame_id is
// --frame-id (default velodyne; --other-frame K F: message K's is F); each --tf "parent child x y z qx qy qz qw" is
// one transform of a single TFMessage on --tf-topic (default /tf_static), stamped at the first scan's time.
//
//   scans2bag <scan_folder> <times_file> <out> <ros1|mcap> [--topic T] [--layout L] [--big-endian] [--truncate K]
//             [--tum <trajectory> --pose-topic T] [--frame-id F] [--other-frame K F] [--tf "..."]... [--tf-topic T]
//   scans2bag --have-ros1        exit status 0 when this build writes ROS 1 bags
#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <quasiloc/core/error.h>
#include <quasiloc/map/lidar_scan.h>
#include <quasiloc/ros/bag_writer.h>
#include <quasiloc/ros/message_source.h>
#include <sstream>
#include <string>
#include <vector>

using namespace quasiloc;

namespace
{
/** "1317000000.1" -> 1317000000100000000 ns, exactly (no floating point). */
std::int64_t nanosecondsOf(const std::string& decimal)
{
    const auto dot = decimal.find('.');
    const std::string whole = decimal.substr(0, dot);
    std::string frac = dot == std::string::npos ? "" : decimal.substr(dot + 1);
    core::require(frac.size() <= 9, decimal, "more than 9 decimals");
    frac.resize(9, '0');
    return std::stoll(whole) * 1000000000 + std::stoll(frac);
}

std::vector<std::string> lines(const std::string& path)
{
    std::ifstream in(path);
    core::require(in.good(), path, "cannot be read");
    std::vector<std::string> v;
    for (std::string l; std::getline(in, l);)
        if (!l.empty() && l[0] != '#') v.push_back(l);
    return v;
}

struct Layout
{
    std::vector<ros::PointFieldMsg> fields;
    std::uint32_t point_step = 0;
    bool f64 = false;
};

Layout layoutOf(const std::string& name)
{
    using F = ros::PointFieldMsg;
    if (name == "xyzi32" || name == "no_xyz")
    {
        const bool bad = name == "no_xyz";
        return {{{bad ? "a" : "x", 0, F::kFloat32, 1},
                 {bad ? "b" : "y", 4, F::kFloat32, 1},
                 {bad ? "c" : "z", 8, F::kFloat32, 1},
                 {"intensity", 12, F::kFloat32, 1}},
                16,
                false};
    }
    core::require(name == "organised64", name, "unknown layout (xyzi32, organised64, no_xyz)");
    return {{{"x", 0, F::kFloat64, 1},
             {"y", 8, F::kFloat64, 1},
             {"z", 16, F::kFloat64, 1},
             {"intensity", 24, F::kFloat64, 1}},
            40,
            true};
}

void put(std::vector<std::uint8_t>& data, std::size_t at, double v, bool f64, bool big_endian)
{
    std::uint8_t b[8];
    std::size_t n = f64 ? 8 : 4;
    if (f64)
        std::memcpy(b, &v, 8);
    else
    {
        const float f = float(v);
        std::memcpy(b, &f, 4);
    }
    for (std::size_t k = 0; k < n; ++k) data[at + k] = big_endian ? b[n - 1 - k] : b[k];
}

ros::PointCloud2Msg cloudOf(const map::LidarScan& scan, const Layout& L, bool organised, bool big_endian)
{
    ros::PointCloud2Msg m;
    m.fields = L.fields;
    m.point_step = L.point_step;
    m.is_bigendian = big_endian;
    const std::size_t n = scan.size();
    // Organised: 2 rows, each led by a NaN point and filled up with NaN points; rows padded by 8 bytes.
    const std::size_t per_row = organised ? (n + 1) / 2 : n;
    m.height = organised ? 2 : 1;
    m.width = std::uint32_t(organised ? per_row + 2 : n);
    m.row_step = m.width * m.point_step + (organised ? 8 : 0);
    m.is_dense = !organised;
    m.data.assign(std::size_t(m.row_step) * m.height, 0);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::size_t k = 0;
    for (std::uint32_t r = 0; r < m.height; ++r)
        for (std::uint32_t c = 0; c < m.width; ++c)
        {
            const bool valid = !organised ? true : c >= 1 && c <= per_row && k < n;
            const std::size_t at = std::size_t(r) * m.row_step + std::size_t(c) * m.point_step;
            for (int f = 0; f < 4; ++f)
            {
                const double v = !valid ? nan : f < 3 ? double(scan.points[k][f]) : double(scan.intensity[k]);
                put(m.data, at + L.fields[f].offset, v, L.f64, big_endian);
            }
            if (valid) ++k;
        }
    return m;
}
}  // namespace

int main(int argc, char** argv)
{
    if (argc == 2 && std::string(argv[1]) == "--have-ros1") return ros::haveRos1() ? 0 : 1;
    if (argc < 5)
    {
        std::cerr
            << "usage: scans2bag <scan_folder> <times_file> <out> <ros1|mcap> [--topic T] [--layout L] "
               "[--big-endian] [--truncate K] [--tum <trajectory> --pose-topic T] [--frame-id F] [--other-frame K F] "
               "[--tf \"parent child x y z qx qy qz qw\"]... [--tf-topic T]\n";
        return 2;
    }
    try
    {
        std::string topic = "/points", layout = "xyzi32", tum, pose_topic;
        bool big_endian = false;
        long truncate = -1, other_frame_message = -1;
        std::string frame_id = "velodyne", other_frame, tf_topic = "/tf_static";
        std::vector<std::string> tf;
        for (int a = 5; a < argc; ++a)
        {
            const std::string k = argv[a];
            const auto value = [&] {
                core::require(a + 1 < argc, k, "needs a value");
                return std::string(argv[++a]);
            };
            if (k == "--topic")
                topic = value();
            else if (k == "--layout")
                layout = value();
            else if (k == "--big-endian")
                big_endian = true;
            else if (k == "--truncate")
                truncate = std::stol(value());
            else if (k == "--tum")
                tum = value();
            else if (k == "--pose-topic")
                pose_topic = value();
            else if (k == "--frame-id")
                frame_id = value();
            else if (k == "--other-frame")
            {
                other_frame_message = std::stol(value());
                other_frame = value();
            }
            else if (k == "--tf")
                tf.push_back(value());
            else if (k == "--tf-topic")
                tf_topic = value();
            else
                throw core::InputError(k, "unknown argument");
        }
        const map::FolderScanSource scans(argv[1], map::CloudFormat::Auto);
        const std::vector<std::string> times = lines(argv[2]);
        core::require(times.size() >= scans.size(), argv[2], "fewer times than scans");
        const std::string format = argv[4];
        core::require(format == "ros1" || format == "mcap", format, "ros1 or mcap");
        const Layout L = layoutOf(layout);
        ros::BagWriter bag(argv[3], format == "ros1" ? dataset::BagFormat::Ros1 : dataset::BagFormat::Mcap);
        if (!tf.empty())
        {
            std::vector<ros::TransformMsg> transforms;
            for (const std::string& text : tf)
            {
                std::istringstream s(text);
                ros::TransformMsg t;
                double q[4];
                s >> t.header.frame_id >> t.child_frame_id >> t.translation.x() >> t.translation.y() >>
                    t.translation.z() >> q[0] >> q[1] >> q[2] >> q[3];
                core::require(!s.fail(), text, "--tf needs: parent child x y z qx qy qz qw");
                t.header.stamp_ns = nanosecondsOf(times.at(0));
                t.rotation = Eigen::Quaterniond(q[3], q[0], q[1], q[2]);
                transforms.push_back(t);
            }
            bag.tfStatic(tf_topic, transforms);
        }
        for (std::size_t i = 0; i < scans.size(); ++i)
        {
            ros::PointCloud2Msg m = cloudOf(scans.read(i), L, layout == "organised64", big_endian);
            m.header = {nanosecondsOf(times[i]), long(i) == other_frame_message ? other_frame : frame_id};
            if (long(i) == truncate) m.data.resize(m.data.size() / 2);
            bag.pointCloud2(topic, m);
        }
        if (!tum.empty())
            for (const std::string& l : lines(tum))
            {
                std::istringstream s(l);
                std::string t;
                ros::PoseMsg p;
                double q[4];
                s >> t >> p.position.x() >> p.position.y() >> p.position.z() >> q[0] >> q[1] >> q[2] >> q[3];
                p.header = {nanosecondsOf(t), "map"};
                p.orientation = Eigen::Quaterniond(q[3], q[0], q[1], q[2]);
                bag.pose(pose_topic, p);
            }
        bag.close();
        std::cout << "wrote " << scans.size() << " scans to " << argv[3] << "\n";
    }
    catch (const std::exception& e)
    {
        std::cerr << "scans2bag: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
