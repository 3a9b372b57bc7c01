#pragma once
// sensor_msgs/PointCloud2, the LiDAR scans of ROS 1 and ROS 2 bags: the message as a plain struct (read from CDR by
// cdr::readPointCloud2, from ROS 1 bags by Debian's roscpp serialisation), and the scan map-build takes from it
// (scanFromPointCloud2): the points' fields chosen and decoded by libs/map's conventions (point_records.h, the same
// field names and time units as the PCD and PLY readers).
#include <cstdint>
#include <quasiloc/map/lidar_scan.h>
#include <quasiloc/ros/cdr.h>
#include <quasiloc/ros/messages.h>
#include <string>
#include <vector>

namespace quasiloc::ros
{
namespace types
{
constexpr const char* kPointCloud2 = "sensor_msgs/PointCloud2";
}

/** sensor_msgs/PointField */
struct PointFieldMsg
{
    std::string name;
    std::uint32_t offset = 0;   ///< bytes from the start of a point
    std::uint8_t datatype = 0;  ///< kInt8 ... kFloat64
    std::uint32_t count = 1;    ///< values of the field per point

    static constexpr std::uint8_t kInt8 = 1, kUInt8 = 2, kInt16 = 3, kUInt16 = 4, kInt32 = 5, kUInt32 = 6, kFloat32 = 7,
                                  kFloat64 = 8;
};

/** sensor_msgs/PointCloud2: height rows of width points; point (r, c) at data[r * row_step + c * point_step]. */
struct PointCloud2Msg
{
    MsgHeader header;
    std::uint32_t height = 0, width = 0;
    std::vector<PointFieldMsg> fields;
    bool is_bigendian = false;
    std::uint32_t point_step = 0, row_step = 0;
    std::vector<std::uint8_t> data;
    bool is_dense = false;
};

/** The scan of a message: x y z (float32 or float64), the intensity (intensity, reflectivity, ... of any numeric
 *  type), the per-point time (time s, t ns, offset_time ns, timestamp absolute s) and ring (ring, line, laser_id)
 *  where the message has them; points without a position (NaN x, y or z: an organised cloud's invalid returns) are
 *  dropped and counted in invalid_points. InputError naming `name` for a message without x, y or z or an intensity,
 *  a field read that is not a PointField datatype or does not fit in point_step, or data shorter than height rows of
 *  width points need (truncated). */
map::LidarScan scanFromPointCloud2(const PointCloud2Msg& m, const std::string& name);

namespace cdr
{
/** The whole message; InputError naming the Reader's `where` when it does not decode. */
PointCloud2Msg readPointCloud2(Reader& r);
/** A complete little-endian CDR message with its encapsulation header. */
std::vector<std::uint8_t> encode(const PointCloud2Msg& m);
}  // namespace cdr

}  // namespace quasiloc::ros
