// PLY reader: header parsing, then the elements in file order; only the "vertex" element is decoded,
// every other element is walked over (needed because list properties make their size variable).
#include <algorithm>
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/map/map_import.h>
#include <quasiloc/map/point_records.h>

#include "file_bytes.h"
#include "scalar_types.h"

namespace quasiloc::map
{
namespace
{
using detail::ScalarType;

struct PlyProperty
{
    std::string name;
    ScalarType type = ScalarType::Float32;  ///< item type for a list
    bool is_list = false;
    ScalarType count_type = ScalarType::UInt8;
};

struct PlyElement
{
    std::string name;
    size_t count = 0;
    std::vector<PlyProperty> properties;
};

enum class PlyEncoding
{
    Ascii,
    BinaryLE,
    BinaryBE
};

struct PlyHeader
{
    PlyEncoding encoding = PlyEncoding::Ascii;
    std::string encoding_name;
    std::vector<PlyElement> elements;
    size_t data_offset = 0;
};

ScalarType parseType(const std::string& name, const std::string& path, size_t line_no)
{
    ScalarType t;
    core::require(detail::plyTypeFromName(name, t), path,
                  "header line " + std::to_string(line_no) + ": unknown PLY type '" + name + "'");
    return t;
}

PlyHeader parseHeader(const std::vector<uint8_t>& bytes, const std::string& path)
{
    PlyHeader h;
    size_t pos = 0, line_no = 0;
    bool have_format = false, ended = false;
    while (pos < bytes.size() && !ended)
    {
        size_t eol = pos;
        while (eol < bytes.size() && bytes[eol] != '\n') ++eol;
        core::require(eol < bytes.size(), path, "PLY header has no end_header line");
        const std::string line(reinterpret_cast<const char*>(bytes.data() + pos), eol - pos);
        pos = eol + 1;
        ++line_no;
        const auto w = detail::splitWords(line);
        const std::string where = "header line " + std::to_string(line_no);
        if (line_no == 1)
        {
            core::require(w.size() == 1 && w[0] == "ply", path, "not a PLY file (first line is not 'ply')");
            continue;
        }
        if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
        if (w[0] == "format")
        {
            core::require(w.size() >= 2, path, where + ": format line without encoding");
            h.encoding_name = w[1];
            if (w[1] == "ascii")
                h.encoding = PlyEncoding::Ascii;
            else if (w[1] == "binary_little_endian")
                h.encoding = PlyEncoding::BinaryLE;
            else if (w[1] == "binary_big_endian")
                h.encoding = PlyEncoding::BinaryBE;
            else
                throw core::InputError(path, where + ": unknown PLY encoding '" + w[1] + "'");
            have_format = true;
        }
        else if (w[0] == "element")
        {
            core::require(w.size() == 3, path, where + ": expected 'element <name> <count>'");
            // Every instance takes at least one byte of the file: a larger count is a lie (and would size
            // allocations and loops).
            double value = -1;
            size_t count = 0;
            core::require(detail::parseNumber(w[2], value) && detail::countInRange(value, bytes.size(), count), path,
                          where + ": bad element count '" + w[2] + "' (a whole number, at most the file size " +
                              std::to_string(bytes.size()) + ")");
            h.elements.push_back({w[1], count, {}});
        }
        else if (w[0] == "property")
        {
            core::require(!h.elements.empty(), path, where + ": property before any element");
            PlyProperty p;
            if (w.size() == 5 && w[1] == "list")
            {
                p.is_list = true;
                p.count_type = parseType(w[2], path, line_no);
                p.type = parseType(w[3], path, line_no);
                p.name = w[4];
            }
            else
            {
                core::require(w.size() == 3, path, where + ": expected 'property <type> <name>'");
                p.type = parseType(w[1], path, line_no);
                p.name = w[2];
            }
            h.elements.back().properties.push_back(p);
        }
        else if (w[0] == "end_header")
            ended = true;
        else
            throw core::InputError(path, where + ": unexpected keyword '" + w[0] + "'");
    }
    core::require(ended, path, "PLY header has no end_header line");
    core::require(have_format, path, "PLY header has no format line");
    h.data_offset = pos;
    return h;
}

/** Which properties of the vertex element hold x, y, z, the intensity, the time and the ring (list properties take
 *  no role). */
using VertexLayout = CloudFieldRoles;

VertexLayout findVertexLayout(const PlyElement& vertex, const std::string& path, std::string& intensity_name)
{
    std::vector<std::string> names;
    std::vector<bool> usable;
    std::string list;
    for (const auto& p : vertex.properties)
    {
        names.push_back(p.name);
        usable.push_back(!p.is_list);
        list += (list.empty() ? "" : " ") + p.name;
    }
    const VertexLayout L = cloudFieldRoles(names, usable);
    core::require(L.hasXyz(), path, "the vertex element lacks x, y or z (properties: " + list + ")");
    core::require(L.intensity >= 0, path,
                  "no intensity field: the vertex element has no property named intensity, reflectivity, "
                  "reflectance, scalar_* or i (properties: " +
                      list + ")");
    intensity_name = names[size_t(L.intensity)];
    return L;
}

[[noreturn]] void throwTruncated(const std::string& path, const PlyElement& el, size_t instance)
{
    throw core::InputError(path, "truncated binary data: the file ends inside element '" + el.name + "' #" +
                                     std::to_string(instance) + " of " + std::to_string(el.count));
}

/** Binary: walks one element instance starting at `pos`; records the offsets of the scalar properties
 *  in `offsets` if non-null. Returns the position after the instance. */
size_t walkBinaryInstance(const std::vector<uint8_t>& bytes, size_t pos, const PlyElement& el, bool swap,
                          size_t* offsets, const std::string& path, size_t instance)
{
    for (size_t k = 0; k < el.properties.size(); ++k)
    {
        const auto& p = el.properties[k];
        size_t n_bytes = detail::sizeOf(p.type);
        if (p.is_list)
        {
            const size_t cs = detail::sizeOf(p.count_type);
            if (pos + cs > bytes.size()) throwTruncated(path, el, instance);
            const double value = detail::decodeScalar(&bytes[pos], p.count_type, swap);
            size_t count = 0;
            if (!detail::countInRange(value, bytes.size(), count))
                throw core::InputError(path, "bad list length " + std::to_string(value) + " in element '" + el.name +
                                                 "' #" + std::to_string(instance));
            pos += cs;
            n_bytes *= count;  // <= 8 * file size: no overflow
        }
        else if (offsets)
            offsets[k] = pos;
        if (pos + n_bytes > bytes.size()) throwTruncated(path, el, instance);
        pos += n_bytes;
    }
    return pos;
}

bool hasList(const PlyElement& el)
{
    for (const auto& p : el.properties)
        if (p.is_list) return true;
    return false;
}

void readBinary(const std::vector<uint8_t>& bytes, const PlyHeader& h, size_t vertex_el, const VertexLayout& L,
                const std::string& path, RawCloud& cloud)
{
    const bool file_big = h.encoding == PlyEncoding::BinaryBE;
    const bool swap = file_big != detail::hostIsBigEndian();
    size_t pos = h.data_offset;
    for (size_t e = 0; e < vertex_el; ++e)  // elements before the vertices: skip
    {
        const PlyElement& el = h.elements[e];
        if (!hasList(el))
        {
            size_t stride = 0;
            for (const auto& p : el.properties) stride += detail::sizeOf(p.type);
            core::require(pos + stride * el.count <= bytes.size(), path,
                          "truncated binary data: the file ends inside element '" + el.name + "'");
            pos += stride * el.count;
        }
        else
            for (size_t i = 0; i < el.count; ++i) pos = walkBinaryInstance(bytes, pos, el, swap, nullptr, path, i);
    }
    const PlyElement& v = h.elements[vertex_el];
    std::vector<size_t> offsets(v.properties.size(), 0);
    const auto& P = v.properties;
    const int want[4] = {L.x, L.y, L.z, L.intensity};
    auto decodeVertex = [&](const uint8_t* record_base, const size_t* off) {
        float val[4];
        for (int c = 0; c < 4; ++c)
            val[c] = static_cast<float>(detail::decodeScalar(record_base + off[want[c]], P[want[c]].type, swap));
        cloud.push(val[0], val[1], val[2], val[3]);
        if (L.time >= 0) cloud.time.push_back(detail::decodeScalar(record_base + off[L.time], P[L.time].type, swap));
        if (L.ring >= 0)
            cloud.ring.push_back(ringNumber(detail::decodeScalar(record_base + off[L.ring], P[L.ring].type, swap)));
    };
    if (v.count == 0) return;
    if (!hasList(v))
    {
        // Fixed-size records: one bounds check, then straight decoding. Property 0 starts the record.
        const size_t start = pos;
        const size_t stride = walkBinaryInstance(bytes, pos, v, swap, offsets.data(), path, 0) - start;
        for (auto& o : offsets) o -= start;
        if (start + stride * v.count > bytes.size())
            throwTruncated(path, v, (bytes.size() - start) / std::max<size_t>(stride, 1));
        cloud.reserve(v.count);
        for (size_t i = 0; i < v.count; ++i) decodeVertex(bytes.data() + start + i * stride, offsets.data());
        return;
    }
    for (size_t i = 0; i < v.count; ++i)
    {
        pos = walkBinaryInstance(bytes, pos, v, swap, offsets.data(), path, i);
        decodeVertex(bytes.data(), offsets.data());
    }
}

void readAscii(const std::vector<uint8_t>& bytes, const PlyHeader& h, size_t vertex_el, const VertexLayout& L,
               const std::string& path, RawCloud& cloud)
{
    detail::TokenCursor cur(bytes.data() + h.data_offset, bytes.data() + bytes.size());
    std::vector<double> values;
    for (size_t e = 0; e <= vertex_el; ++e)
    {
        const PlyElement& el = h.elements[e];
        const bool is_vertex = e == vertex_el;
        // A vertex takes at least two characters per property (value and blank): reserve no more than fits.
        if (is_vertex) cloud.reserve(std::min(el.count, (bytes.size() - h.data_offset) / (2 * el.properties.size())));
        values.assign(el.properties.size(), 0.0);
        const std::string what = "element '" + el.name + "'";
        for (size_t i = 0; i < el.count; ++i)
        {
            for (size_t k = 0; k < el.properties.size(); ++k)
            {
                const auto& p = el.properties[k];
                if (p.is_list)
                {
                    const double value = cur.number(path, what.c_str(), i);
                    size_t n = 0;
                    if (!detail::countInRange(value, bytes.size(), n))
                        throw core::InputError(path, "bad list length in " + what + " #" + std::to_string(i));
                    for (size_t j = 0; j < n; ++j) cur.number(path, what.c_str(), i);
                }
                else
                    values[k] = cur.number(path, what.c_str(), i);
            }
            if (!is_vertex) continue;
            cloud.push(static_cast<float>(values[L.x]), static_cast<float>(values[L.y]),
                       static_cast<float>(values[L.z]), static_cast<float>(values[L.intensity]));
            if (L.time >= 0) cloud.time.push_back(values[L.time]);
            if (L.ring >= 0) cloud.ring.push_back(ringNumber(values[L.ring]));
        }
    }
}

}  // namespace

RawCloud readPly(const std::string& path) { return detail::parsePly(detail::readFileBytes(path), path); }

RawCloud detail::parsePly(const std::vector<uint8_t>& bytes, const std::string& path)
{
    const PlyHeader h = parseHeader(bytes, path);
    size_t vertex_el = h.elements.size();
    for (size_t e = 0; e < h.elements.size(); ++e)
        if (h.elements[e].name == "vertex")
        {
            vertex_el = e;
            break;
        }
    core::require(vertex_el < h.elements.size(), path, "PLY file has no 'vertex' element");
    RawCloud cloud;
    cloud.encoding = h.encoding_name;
    const VertexLayout L = findVertexLayout(h.elements[vertex_el], path, cloud.intensity_field);
    if (L.time >= 0) cloud.time_field = h.elements[vertex_el].properties[L.time].name;
    if (L.ring >= 0) cloud.ring_field = h.elements[vertex_el].properties[L.ring].name;
    if (h.encoding == PlyEncoding::Ascii)
        readAscii(bytes, h, vertex_el, L, path, cloud);
    else
        readBinary(bytes, h, vertex_el, L, path, cloud);
    return cloud;
}

}  // namespace quasiloc::map
