// ROS 1 PointCloud2 conversions (ros1_point_cloud2.h).
#include "ros1_point_cloud2.h"

#include "ros1_messages.h"

namespace quasiloc::ros::ros1
{
PointCloud2Msg fromRos1(sensor_msgs::PointCloud2&& m)
{
    PointCloud2Msg r;
    r.header = fromRos1(m.header);
    r.height = m.height;
    r.width = m.width;
    for (const sensor_msgs::PointField& f : m.fields) r.fields.push_back({f.name, f.offset, f.datatype, f.count});
    r.is_bigendian = m.is_bigendian != 0;
    r.point_step = m.point_step;
    r.row_step = m.row_step;
    r.data = std::move(m.data);
    r.is_dense = m.is_dense != 0;
    return r;
}

sensor_msgs::PointCloud2 toRos1(const PointCloud2Msg& m, std::uint32_t seq)
{
    sensor_msgs::PointCloud2 r;
    r.header = toRos1(m.header, seq);
    r.height = m.height;
    r.width = m.width;
    for (const PointFieldMsg& f : m.fields)
    {
        sensor_msgs::PointField p;
        p.name = f.name;
        p.offset = f.offset;
        p.datatype = f.datatype;
        p.count = f.count;
        r.fields.push_back(p);
    }
    r.is_bigendian = m.is_bigendian;
    r.point_step = m.point_step;
    r.row_step = m.row_step;
    r.data = m.data;
    r.is_dense = m.is_dense;
    return r;
}

}  // namespace quasiloc::ros::ros1
