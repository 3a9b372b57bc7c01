// PCD (v0.7) reader: ascii, binary (point after point) and binary_compressed (LZF, field after field).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <quasiloc/core/error.h>
#include <quasiloc/map/lzf.h>
#include <quasiloc/map/map_import.h>
#include <quasiloc/map/point_records.h>

#include "file_bytes.h"
#include "scalar_types.h"

namespace quasiloc::map
{
namespace
{
using detail::ScalarType;

struct PcdField
{
    std::string name;
    int size = 4;
    char type = 'F';
    size_t count = 1;
    ScalarType scalar = ScalarType::Float32;
    size_t offset = 0;  ///< byte offset inside one point record (binary layout)
};

struct PcdHeader
{
    std::vector<PcdField> fields;
    size_t width = 0, height = 1, points = 0;
    bool have_points = false;
    std::string data;  ///< ascii | binary | binary_compressed
    size_t data_offset = 0;
    size_t record_size = 0;
};

size_t parseCount(const std::string& s, const std::string& path, const std::string& key)
{
    // Bounded so that products of counts cannot overflow silently (they are multiplied with detail::multiply).
    constexpr size_t kMaxCount = size_t(1) << 40;
    double v = -1;
    size_t count = 0;
    core::require(detail::parseNumber(s, v) && detail::countInRange(v, kMaxCount, count), path,
                  "PCD header: bad " + key + " value '" + s + "'");
    return count;
}

void parseHeaderLine(const std::vector<std::string>& w, PcdHeader& h, std::vector<std::string>& sizes,
                     std::vector<std::string>& types, std::vector<std::string>& counts, const std::string& path)
{
    const std::string key = detail::lowerCase(w[0]);
    if (key == "version" || key == "viewpoint") return;
    if (key == "fields" || key == "columns")
        for (size_t k = 1; k < w.size(); ++k) h.fields.push_back({w[k]});
    else if (key == "size")
        sizes.assign(w.begin() + 1, w.end());
    else if (key == "type")
        types.assign(w.begin() + 1, w.end());
    else if (key == "count")
        counts.assign(w.begin() + 1, w.end());
    else if (key == "width" && w.size() == 2)
        h.width = parseCount(w[1], path, "WIDTH");
    else if (key == "height" && w.size() == 2)
        h.height = parseCount(w[1], path, "HEIGHT");
    else if (key == "points" && w.size() == 2)
    {
        h.points = parseCount(w[1], path, "POINTS");
        h.have_points = true;
    }
    else if (key == "data" && w.size() == 2)
        h.data = detail::lowerCase(w[1]);
    else
        throw core::InputError(path, "PCD header: unexpected line starting with '" + w[0] + "'");
}

/** Checks and completes the field list (SIZE/TYPE/COUNT per field, offsets, record size). */
void finishFields(PcdHeader& h, const std::vector<std::string>& sizes, const std::vector<std::string>& types,
                  const std::vector<std::string>& counts, const std::string& path)
{
    core::require(!h.fields.empty(), path, "PCD header has no FIELDS line");
    const size_t n = h.fields.size();
    core::require(sizes.size() == n, path, "PCD header: SIZE must list one value per field");
    core::require(types.size() == n, path, "PCD header: TYPE must list one value per field");
    core::require(counts.empty() || counts.size() == n, path, "PCD header: COUNT must list one value per field");
    size_t offset = 0;
    for (size_t k = 0; k < n; ++k)
    {
        PcdField& f = h.fields[k];
        f.size = static_cast<int>(parseCount(sizes[k], path, "SIZE"));
        core::require(types[k].size() == 1, path, "PCD header: bad TYPE '" + types[k] + "'");
        f.type = static_cast<char>(std::toupper(static_cast<unsigned char>(types[k][0])));
        core::require(detail::pcdType(f.type, f.size, f.scalar), path,
                      "PCD header: field '" + f.name + "' has an unsupported TYPE/SIZE " + types[k] + "/" + sizes[k]);
        f.count = counts.empty() ? 1 : parseCount(counts[k], path, "COUNT");
        // A field with COUNT 0 takes no byte of a record, yet its first value would be read (found by fuzz_pcd:
        // a heap-buffer-overflow).
        core::require(f.count >= 1, path, "PCD header: field '" + f.name + "' has COUNT 0");
        f.offset = offset;
        size_t field_bytes = 0;
        core::require(detail::multiply(static_cast<size_t>(f.size), f.count, field_bytes) &&
                          !__builtin_add_overflow(offset, field_bytes, &offset),
                      path, "PCD header: the point record size overflows (COUNT too large)");
    }
    h.record_size = offset;
    size_t width_x_height = 0;
    core::require(
        detail::multiply(h.width, h.height, width_x_height), path,
        "PCD header: WIDTH * HEIGHT overflows (" + std::to_string(h.width) + " * " + std::to_string(h.height) + ")");
    if (!h.have_points) h.points = width_x_height;
    core::require(h.points == width_x_height, path,
                  "PCD header: POINTS (" + std::to_string(h.points) + ") != WIDTH * HEIGHT (" +
                      std::to_string(h.width) + " * " + std::to_string(h.height) + ")");
}

PcdHeader parseHeader(const std::vector<uint8_t>& bytes, const std::string& path)
{
    PcdHeader h;
    std::vector<std::string> sizes, types, counts;
    size_t pos = 0;
    while (h.data.empty())
    {
        core::require(pos < bytes.size(), path, "PCD header has no DATA line (not a PCD file?)");
        size_t eol = pos;
        while (eol < bytes.size() && bytes[eol] != '\n') ++eol;
        std::string line(reinterpret_cast<const char*>(bytes.data() + pos), eol - pos);
        pos = std::min(eol + 1, bytes.size());
        if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
        const auto w = detail::splitWords(line);
        if (w.empty()) continue;
        parseHeaderLine(w, h, sizes, types, counts, path);
    }
    core::require(h.data == "ascii" || h.data == "binary" || h.data == "binary_compressed", path,
                  "PCD header: unknown DATA encoding '" + h.data + "'");
    finishFields(h, sizes, types, counts, path);
    h.data_offset = pos;
    return h;
}

using FieldChoice = CloudFieldRoles;

FieldChoice chooseFields(const PcdHeader& h, const std::string& path, std::string& intensity_name)
{
    std::vector<std::string> names;
    for (const PcdField& f : h.fields) names.push_back(f.name);
    const FieldChoice c = cloudFieldRoles(names);
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : " ") + n;
    core::require(c.hasXyz(), path, "PCD fields lack x, y or z (fields: " + list + ")");
    core::require(c.intensity >= 0, path,
                  "no intensity field: the PCD has no field named intensity, reflectivity, reflectance, i or "
                  "scalar_* (fields: " +
                      list + ")");
    intensity_name = names[size_t(c.intensity)];
    return c;
}

void readAscii(const std::vector<uint8_t>& bytes, const PcdHeader& h, const FieldChoice& c, const std::string& path,
               RawCloud& cloud)
{
    detail::TokenCursor cur(bytes.data() + h.data_offset, bytes.data() + bytes.size());
    std::vector<double> first(h.fields.size(), 0.0);
    // A point takes at least two characters per field (value and blank): reserve no more than the data can hold.
    cloud.reserve(std::min(h.points, (bytes.size() - h.data_offset) / (2 * h.fields.size())));
    for (size_t i = 0; i < h.points; ++i)
    {
        for (size_t k = 0; k < h.fields.size(); ++k)
            for (size_t j = 0; j < h.fields[k].count; ++j)
            {
                const double v = cur.number(path, "point", i);
                if (j == 0) first[k] = v;
            }
        cloud.push(static_cast<float>(first[c.x]), static_cast<float>(first[c.y]), static_cast<float>(first[c.z]),
                   static_cast<float>(first[c.intensity]));
        if (c.time >= 0) cloud.time.push_back(first[c.time]);
        if (c.ring >= 0) cloud.ring.push_back(ringNumber(first[c.ring]));
    }
}

/** The fields decoded: x y z intensity, then the optional time and ring (-1: absent). */
void wantedFields(const FieldChoice& c, int idx[6])
{
    const int all[6] = {c.x, c.y, c.z, c.intensity, c.time, c.ring};
    for (int k = 0; k < 6; ++k) idx[k] = all[k];
}

/** Decodes the wanted fields. Value of field f for point i is at base[f] + i * stride[f]. */
void decodeFields(const uint8_t* data, const PcdHeader& h, const FieldChoice& c, const size_t base[6],
                  const size_t stride[6], RawCloud& cloud)
{
    const bool swap = detail::hostIsBigEndian();  // PCD binary data is little-endian
    int idx[6];
    wantedFields(c, idx);
    ScalarType t[6];
    for (int k = 0; k < 6; ++k) t[k] = idx[k] >= 0 ? h.fields[idx[k]].scalar : ScalarType::Float32;
    cloud.reserve(h.points);  // the callers checked that the data holds h.points records
    if (c.time >= 0) cloud.time.reserve(h.points);
    if (c.ring >= 0) cloud.ring.reserve(h.points);
    for (size_t i = 0; i < h.points; ++i)
    {
        float v[4];
        for (int k = 0; k < 4; ++k)
            v[k] = static_cast<float>(detail::decodeScalar(data + base[k] + i * stride[k], t[k], swap));
        cloud.push(v[0], v[1], v[2], v[3]);
        if (c.time >= 0) cloud.time.push_back(detail::decodeScalar(data + base[4] + i * stride[4], t[4], swap));
        if (c.ring >= 0)
            cloud.ring.push_back(ringNumber(detail::decodeScalar(data + base[5] + i * stride[5], t[5], swap)));
    }
}

void readBinary(const std::vector<uint8_t>& bytes, const PcdHeader& h, const FieldChoice& c, const std::string& path,
                RawCloud& cloud)
{
    size_t need = 0;
    const size_t have = bytes.size() - h.data_offset;
    core::require(detail::multiply(h.points, h.record_size, need) && have >= need, path,
                  "truncated binary data: " + std::to_string(h.points) + " points need " + std::to_string(need) +
                      " bytes, the file holds " + std::to_string(have));
    int idx[6];
    wantedFields(c, idx);
    size_t base[6] = {0, 0, 0, 0, 0, 0}, stride[6] = {0, 0, 0, 0, 0, 0};
    for (int k = 0; k < 6; ++k)
    {
        if (idx[k] < 0) continue;
        base[k] = h.fields[idx[k]].offset;
        stride[k] = h.record_size;
    }
    decodeFields(bytes.data() + h.data_offset, h, c, base, stride, cloud);
}

void readCompressed(const std::vector<uint8_t>& bytes, const PcdHeader& h, const FieldChoice& c,
                    const std::string& path, RawCloud& cloud)
{
    const size_t have = bytes.size() - h.data_offset;
    core::require(have >= 8, path, "truncated binary_compressed data: no size header");
    uint32_t sizes[2];  // compressed, uncompressed (little-endian)
    for (int k = 0; k < 2; ++k)
        sizes[k] = static_cast<uint32_t>(
            detail::decodeScalar(bytes.data() + h.data_offset + 4 * k, ScalarType::UInt32, detail::hostIsBigEndian()));
    size_t need = 0;
    core::require(detail::multiply(h.points, h.record_size, need) && sizes[1] == need, path,
                  "binary_compressed: uncompressed size " + std::to_string(sizes[1]) +
                      " != " + std::to_string(h.points) + " points * " + std::to_string(h.record_size) + " bytes");
    core::require(have - 8 >= sizes[0], path,
                  "truncated binary_compressed data: " + std::to_string(sizes[0]) + " compressed bytes announced, " +
                      std::to_string(have - 8) + " present");
    // Checked before allocating: the announced size is a length field, LZF cannot expand more than this.
    core::require(need <= uint64_t(sizes[0]) * kLzfMaxExpansion, path,
                  "binary_compressed: " + std::to_string(sizes[0]) + " compressed bytes cannot hold " +
                      std::to_string(need) + " uncompressed bytes (LZF expands at most " +
                      std::to_string(kLzfMaxExpansion) + " times)");
    std::vector<uint8_t> raw(need);
    const auto n = lzfDecompress(bytes.data() + h.data_offset + 8, sizes[0], raw.data(), raw.size());
    core::require(n.has_value() && *n == need, path, "binary_compressed: corrupt LZF data");
    // Decompressed layout: each field's values for all points, one field after the other.
    int idx[6];
    wantedFields(c, idx);
    size_t base[6] = {0, 0, 0, 0, 0, 0}, stride[6] = {0, 0, 0, 0, 0, 0};
    for (int k = 0; k < 6; ++k)
    {
        if (idx[k] < 0) continue;
        const PcdField& f = h.fields[idx[k]];
        base[k] = f.offset * h.points;
        stride[k] = static_cast<size_t>(f.size) * f.count;
    }
    decodeFields(raw.data(), h, c, base, stride, cloud);
}

}  // namespace

RawCloud readPcd(const std::string& path) { return detail::parsePcd(detail::readFileBytes(path), path); }

RawCloud detail::parsePcd(const std::vector<uint8_t>& bytes, const std::string& path)
{
    const PcdHeader h = parseHeader(bytes, path);
    RawCloud cloud;
    cloud.encoding = h.data;
    const FieldChoice c = chooseFields(h, path, cloud.intensity_field);
    if (c.time >= 0) cloud.time_field = h.fields[c.time].name;
    if (c.ring >= 0) cloud.ring_field = h.fields[c.ring].name;
    if (h.data == "ascii")
        readAscii(bytes, h, c, path, cloud);
    else if (h.data == "binary")
        readBinary(bytes, h, c, path, cloud);
    else
        readCompressed(bytes, h, c, path, cloud);
    return cloud;
}

}  // namespace quasiloc::map
