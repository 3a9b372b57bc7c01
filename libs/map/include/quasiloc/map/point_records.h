#pragma once
// Cloud fields as every cloud reader names them, and points stored as fixed-size records of typed fields.
//  - The naming conventions (cloudFieldRoles): which field is x, y, z, the intensity, the per-point time and the ring,
//    from intensityFieldRank, timeFieldRank and isRingField (map_import.h). The PLY and PCD readers and the
//    PointCloud2 decoding of map-build's bag scans (libs/ros point_cloud2.h) all choose their fields with it.
//  - Records (decodePointRecords): rows x columns of records, each field at its byte offset in a record, in either
//    byte order, as ROS's sensor_msgs/PointCloud2 stores points (an organised cloud has rows > 1; rows may be padded:
//    row_step >= columns * point_step). Records without a position (non-finite x, y or z: the invalid returns of an
//    organised cloud) are dropped and counted.
#include <cstdint>
#include <quasiloc/map/map_import.h>
#include <string>
#include <vector>

namespace quasiloc::map
{
/** The numeric types of cloud fields (PLY properties, PCD fields, PointCloud2 fields). */
enum class ScalarType
{
    Int8,
    UInt8,
    Int16,
    UInt16,
    Int32,
    UInt32,
    Int64,
    UInt64,
    Float32,
    Float64
};

/** The field of each role, an index into the names given; -1: absent. */
struct CloudFieldRoles
{
    int x = -1, y = -1, z = -1;
    int intensity = -1;  ///< the lowest positive intensityFieldRank
    int time = -1;       ///< the lowest positive timeFieldRank
    int ring = -1;       ///< the first isRingField
    bool hasXyz() const { return x >= 0 && y >= 0 && z >= 0; }
};

/** Roles by name (x, y and z are matched exactly). A field with usable[k] == false (a PLY list property) takes no
 *  role; an empty `usable` means all are usable. */
CloudFieldRoles cloudFieldRoles(const std::vector<std::string>& names, const std::vector<bool>& usable = {});

/** A ring field's value as a ring number: clamped to [0, 65535]; NaN gives 0. */
uint16_t ringNumber(double value);

struct RecordField
{
    std::string name;
    size_t offset = 0;  ///< bytes from the start of a record
    ScalarType type = ScalarType::Float32;
    size_t count = 1;  ///< values of the field; the first one is read
};

/** rows x columns records; record (r, c) starts at data + r * row_step + c * point_step. */
struct PointRecords
{
    std::vector<RecordField> fields;
    const uint8_t* data = nullptr;
    size_t bytes = 0;  ///< bytes at data
    size_t rows = 0, columns = 0;
    size_t point_step = 0, row_step = 0;
    bool big_endian = false;
};

struct DecodedRecords
{
    RawCloud cloud;      ///< x y z, the raw intensity, and the time and ring where the records have such fields
    size_t invalid = 0;  ///< records without a position (non-finite x, y or z), dropped
};

/** Decodes the fields of cloudFieldRoles. InputError naming `input` when x, y, z or the intensity is missing, when x,
 *  y or z is not float32 / float64 (an integer position would need a scale the records do not carry), when a field
 *  read has count 0 or does not fit in point_step, when rows > 1 and row_step < columns * point_step, when the data
 *  are shorter than the records (the message names the sizes), and when a record with a position has a non-finite
 *  intensity or time. */
DecodedRecords decodePointRecords(const PointRecords& records, const std::string& input);

}  // namespace quasiloc::map
