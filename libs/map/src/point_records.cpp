// Field roles by name and records decoding (point_records.h).
#include <algorithm>
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/map/point_records.h>

#include "file_bytes.h"
#include "scalar_types.h"

namespace quasiloc::map
{
CloudFieldRoles cloudFieldRoles(const std::vector<std::string>& names, const std::vector<bool>& usable)
{
    CloudFieldRoles c;
    int best_rank = 0, best_time_rank = 0;
    for (size_t k = 0; k < names.size(); ++k)
    {
        if (!usable.empty() && !usable[k]) continue;
        const std::string& n = names[k];
        const int i = static_cast<int>(k);
        const int time_rank = timeFieldRank(n);
        if (time_rank > 0 && (best_time_rank == 0 || time_rank < best_time_rank))
            best_time_rank = time_rank, c.time = i;
        if (isRingField(n) && c.ring < 0) c.ring = i;
        if (n == "x") c.x = i;
        if (n == "y") c.y = i;
        if (n == "z") c.z = i;
        const int rank = intensityFieldRank(n);
        if (rank > 0 && (best_rank == 0 || rank < best_rank)) best_rank = rank, c.intensity = i;
    }
    return c;
}

uint16_t ringNumber(double value)
{
    if (!(value >= 0)) return 0;  // also NaN: a cast of NaN to an integer is undefined
    return static_cast<uint16_t>(std::min(value, 65535.0));
}

namespace
{
using detail::multiply;

std::string fieldList(const std::vector<RecordField>& fields)
{
    std::string names;
    for (const RecordField& f : fields) names += (names.empty() ? "" : " ") + f.name;
    return names;
}

/** The roles, with every field read checked against the record layout. */
CloudFieldRoles checkedRoles(const PointRecords& r, const std::string& input)
{
    std::vector<std::string> names;
    for (const RecordField& f : r.fields) names.push_back(f.name);
    const CloudFieldRoles c = cloudFieldRoles(names);
    core::require(c.hasXyz(), input, "fields lack x, y or z (fields: " + fieldList(r.fields) + ")");
    core::require(c.intensity >= 0, input,
                  "no intensity field: no field named intensity, reflectivity, reflectance, scalar_* or i (fields: " +
                      fieldList(r.fields) + ")");
    for (const int k : {c.x, c.y, c.z, c.intensity, c.time, c.ring})
    {
        if (k < 0) continue;
        const RecordField& f = r.fields[size_t(k)];
        core::require(f.count >= 1, input, "field " + f.name + " has count 0");
        const size_t size = detail::sizeOf(f.type);
        core::require(f.offset <= r.point_step && size <= r.point_step - f.offset, input,
                      "field " + f.name + " (" + std::to_string(size) + " bytes at offset " + std::to_string(f.offset) +
                          ") does not fit in a point of point_step " + std::to_string(r.point_step) + " bytes");
    }
    for (const int k : {c.x, c.y, c.z})
    {
        const RecordField& f = r.fields[size_t(k)];
        core::require(f.type == ScalarType::Float32 || f.type == ScalarType::Float64, input,
                      "field " + f.name + " is not float32 or float64 (an integer coordinate carries no scale)");
    }
    return c;
}

void checkSizes(const PointRecords& r, const std::string& input)
{
    if (r.rows == 0 || r.columns == 0) return;
    size_t row_bytes = 0, before_last = 0, need = 0;
    const bool fits = multiply(r.columns, r.point_step, row_bytes) && multiply(r.rows - 1, r.row_step, before_last) &&
                      !__builtin_add_overflow(before_last, row_bytes, &need);
    const std::string shape = std::to_string(r.rows) + (r.rows == 1 ? " row of " : " rows of ") +
                              std::to_string(r.columns) + " points (row_step " + std::to_string(r.row_step) +
                              ", point_step " + std::to_string(r.point_step) + ")";
    core::require(fits, input, shape + " overflow the address space");
    core::require(r.rows == 1 || r.row_step >= row_bytes, input,
                  "row_step " + std::to_string(r.row_step) + " is shorter than a row of " + std::to_string(r.columns) +
                      " points of " + std::to_string(r.point_step) + " bytes");
    core::require(
        r.bytes >= need, input,
        "truncated point data: " + std::to_string(r.bytes) + " bytes, " + shape + " need " + std::to_string(need));
}
}  // namespace

DecodedRecords decodePointRecords(const PointRecords& r, const std::string& input)
{
    const CloudFieldRoles c = checkedRoles(r, input);
    checkSizes(r, input);
    const bool swap = r.big_endian != detail::hostIsBigEndian();
    const int role[6] = {c.x, c.y, c.z, c.intensity, c.time, c.ring};
    size_t offset[6] = {0, 0, 0, 0, 0, 0};
    ScalarType type[6] = {};
    for (int k = 0; k < 6; ++k)
        if (role[k] >= 0) offset[k] = r.fields[size_t(role[k])].offset, type[k] = r.fields[size_t(role[k])].type;

    DecodedRecords d;
    RawCloud& cloud = d.cloud;
    cloud.intensity_field = r.fields[size_t(c.intensity)].name;
    if (c.time >= 0) cloud.time_field = r.fields[size_t(c.time)].name;
    if (c.ring >= 0) cloud.ring_field = r.fields[size_t(c.ring)].name;
    const size_t n = r.rows * r.columns;  // checkSizes: no overflow
    if (n == 0) return d;                 // (without this, 0 columns of 2^32 - 1 rows would loop over the rows)
    cloud.reserve(n);
    if (c.time >= 0) cloud.time.reserve(n);
    if (c.ring >= 0) cloud.ring.reserve(n);
    for (size_t row = 0; row < r.rows; ++row)
        for (size_t col = 0; col < r.columns; ++col)
        {
            const uint8_t* p = r.data + row * r.row_step + col * r.point_step;
            const auto value = [&](int k) { return detail::decodeScalar(p + offset[k], type[k], swap); };
            // As floats: a float64 beyond float's range is no position either.
            const float x = float(value(0)), y = float(value(1)), z = float(value(2));
            if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
            {
                ++d.invalid;
                continue;
            }
            const float intensity = float(value(3));
            const auto where = [&] {
                return "point " + std::to_string(row * r.columns + col) +
                       (r.rows > 1 ? " (row " + std::to_string(row) + ", column " + std::to_string(col) + ")" : "");
            };
            if (!std::isfinite(intensity))
                throw core::InputError(input, where() + " has a position and a non-finite " + cloud.intensity_field);
            cloud.push(x, y, z, intensity);
            if (c.time >= 0)
            {
                const double t = value(4);
                if (!std::isfinite(t))
                    throw core::InputError(input, where() + " has a position and a non-finite " + cloud.time_field);
                cloud.time.push_back(t);
            }
            if (c.ring >= 0) cloud.ring.push_back(ringNumber(value(5)));
        }
    return d;
}

}  // namespace quasiloc::map
