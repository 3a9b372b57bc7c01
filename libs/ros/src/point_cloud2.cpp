// A PointCloud2 message as a LiDAR scan (point_cloud2.h).
#include <quasiloc/core/error.h>
#include <quasiloc/map/point_records.h>
#include <quasiloc/ros/point_cloud2.h>

namespace quasiloc::ros
{
namespace
{
bool scalarType(std::uint8_t datatype, map::ScalarType& t)
{
    using F = PointFieldMsg;
    using map::ScalarType;
    switch (datatype)
    {
        case F::kInt8: t = ScalarType::Int8; return true;
        case F::kUInt8: t = ScalarType::UInt8; return true;
        case F::kInt16: t = ScalarType::Int16; return true;
        case F::kUInt16: t = ScalarType::UInt16; return true;
        case F::kInt32: t = ScalarType::Int32; return true;
        case F::kUInt32: t = ScalarType::UInt32; return true;
        case F::kFloat32: t = ScalarType::Float32; return true;
        case F::kFloat64: t = ScalarType::Float64; return true;
        default: return false;
    }
}
}  // namespace

map::LidarScan scanFromPointCloud2(const PointCloud2Msg& m, const std::string& name)
{
    map::PointRecords records;
    std::vector<std::string> names;
    for (const PointFieldMsg& f : m.fields) names.push_back(f.name);
    const map::CloudFieldRoles roles = map::cloudFieldRoles(names);
    for (std::size_t k = 0; k < m.fields.size(); ++k)
    {
        const PointFieldMsg& f = m.fields[k];
        map::RecordField field{f.name, f.offset, map::ScalarType::Float32, f.count};
        // A field of an unknown datatype that is not read (a vendor's extension) is left out.
        if (!scalarType(f.datatype, field.type))
        {
            const int i = int(k);
            for (const int role : {roles.x, roles.y, roles.z, roles.intensity, roles.time, roles.ring})
                core::require(role != i, name,
                              "PointCloud2 field " + f.name + " has datatype " + std::to_string(f.datatype) +
                                  ", not a PointField datatype (1 int8 ... 8 float64)");
            continue;
        }
        records.fields.push_back(field);
    }
    records.data = m.data.data();
    records.bytes = m.data.size();
    records.rows = m.height;
    records.columns = m.width;
    records.point_step = m.point_step;
    records.row_step = m.row_step;
    records.big_endian = m.is_bigendian;
    map::DecodedRecords decoded = map::decodePointRecords(records, name);
    map::LidarScan scan = map::scanFromCloud(std::move(decoded.cloud), name);
    scan.invalid_points = decoded.invalid;
    return scan;
}

}  // namespace quasiloc::ros
