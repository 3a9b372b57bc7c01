#pragma once
// Test support (included by the *_unittest.cpp files only): a temporary folder, and writers of PLY and
// PCD files with arbitrary field types, counts, extra properties and extra elements, so the readers can
// be checked on layouts the library's own exporter never produces.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <quasiloc/core/error.h>
#include <quasiloc/map/lzf.h>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "scalar_types.h"

namespace quasiloc::map::test
{
using detail::ScalarType;

/** A fresh folder under the system temp folder, removed with its content at destruction. */
class TempDir
{
   public:
    TempDir()
    {
        std::random_device rd;
        path_ = std::filesystem::temp_directory_path() /
                ("quasiloc_map_test_" + std::to_string(rd()) + "_" + std::to_string(rd()));
        std::filesystem::create_directories(path_);
    }
    ~TempDir()
    {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    std::string file(const std::string& name) const { return (path_ / name).string(); }
    const std::filesystem::path& path() const { return path_; }

   private:
    std::filesystem::path path_;
};

/** One field: name, stored type, the value of every point; count > 1 (PCD COUNT) repeats the field with
 *  decoy values after the first element, which is the one readers must use. */
struct Column
{
    std::string name;
    ScalarType type = ScalarType::Float32;
    std::vector<double> values;
    int count = 1;
};

inline const char* plyTypeName(ScalarType t)
{
    switch (t)
    {
        case ScalarType::Int8: return "char";
        case ScalarType::UInt8: return "uchar";
        case ScalarType::Int16: return "short";
        case ScalarType::UInt16: return "ushort";
        case ScalarType::Int32: return "int";
        case ScalarType::UInt32: return "uint";
        case ScalarType::Float32: return "float";
        case ScalarType::Float64: return "double";
        default: return "?";
    }
}

inline void pcdTypeOf(ScalarType t, char& type, int& size)
{
    size = static_cast<int>(detail::sizeOf(t));
    type = (t == ScalarType::Float32 || t == ScalarType::Float64) ? 'F'
           : (t == ScalarType::Int8 || t == ScalarType::Int16 || t == ScalarType::Int32 || t == ScalarType::Int64)
               ? 'I'
               : 'U';
}

/** Appends a value as text (integers without decimals, floats round-trippable). */
inline void appendText(std::ostringstream& s, double v, ScalarType t)
{
    if (t == ScalarType::Float32 || t == ScalarType::Float64)
        s << std::setprecision(17) << v;
    else
        s << static_cast<long long>(v);
}

inline void appendBinary(std::string& out, double v, ScalarType t, bool big_endian)
{
    uint8_t buf[8];
    detail::encodeScalar(v, t, big_endian != detail::hostIsBigEndian(), buf);
    out.append(reinterpret_cast<const char*>(buf), detail::sizeOf(t));
}

/** Optional PLY layout complications. */
struct PlyExtras
{
    bool element_before = false;  ///< an element with a list property before "vertex"
    bool list_in_vertex = false;  ///< a list property between the vertex's columns 1 and 2
    bool element_after = false;   ///< a "face" element after "vertex"
};

/** Writes a PLY with one vertex element made of `cols`. `encoding`: ascii, binary_little_endian,
 *  binary_big_endian. `truncate_bytes` cuts that many bytes off the end. */
inline void writePly(const std::string& path, const std::string& encoding, const std::vector<Column>& cols,
                     const PlyExtras& extras = {}, size_t truncate_bytes = 0)
{
    const size_t n = cols.empty() ? 0 : cols[0].values.size();
    const bool ascii = encoding == "ascii", big = encoding == "binary_big_endian";
    std::ostringstream h;
    h << "ply\nformat " << encoding << " 1.0\ncomment written by a quasiloc unit test\n";
    if (extras.element_before) h << "element material 2\nproperty uchar red\nproperty list uchar int ids\n";
    h << "element vertex " << n << "\n";
    for (size_t c = 0; c < cols.size(); ++c)
    {
        h << "property " << plyTypeName(cols[c].type) << " " << cols[c].name << "\n";
        if (c == 1 && extras.list_in_vertex) h << "property list uchar float extra\n";
    }
    if (extras.element_after) h << "element face 2\nproperty list uchar int vertex_indices\n";
    h << "end_header\n";
    std::string data;
    std::ostringstream text;
    auto put = [&](double v, ScalarType t) {
        if (ascii)
        {
            appendText(text, v, t);
            text << ' ';
        }
        else
            appendBinary(data, v, t, big);
    };
    auto putList = [&](int len, ScalarType item) {
        put(len, ScalarType::UInt8);
        for (int k = 0; k < len; ++k) put(7 + k, item);
    };
    if (extras.element_before)
        for (int m = 0; m < 2; ++m)
        {
            put(200 + m, ScalarType::UInt8);
            putList(m + 2, ScalarType::Int32);
            text << '\n';
        }
    for (size_t i = 0; i < n; ++i)
    {
        for (size_t c = 0; c < cols.size(); ++c)
        {
            put(cols[c].values[i], cols[c].type);
            if (c == 1 && extras.list_in_vertex) putList(static_cast<int>(i % 3), ScalarType::Float32);
        }
        text << '\n';
    }
    if (extras.element_after)
        for (int f = 0; f < 2; ++f)
        {
            putList(3, ScalarType::Int32);
            text << '\n';
        }
    std::string all = h.str() + (ascii ? text.str() : data);
    all.resize(all.size() - std::min(truncate_bytes, all.size()));
    std::ofstream(path, std::ios::binary) << all;
}

/** Writes a PCD v0.7 with `cols` as fields. `data`: ascii, binary, binary_compressed. */
inline void writePcd(const std::string& path, const std::string& data, const std::vector<Column>& cols,
                     size_t truncate_bytes = 0, bool corrupt_lzf = false)
{
    const size_t n = cols.empty() ? 0 : cols[0].values.size();
    std::ostringstream h;
    h << "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS";
    for (const auto& c : cols) h << ' ' << c.name;
    std::ostringstream sizes, types, counts;
    for (const auto& c : cols)
    {
        char t;
        int s;
        pcdTypeOf(c.type, t, s);
        sizes << ' ' << s;
        types << ' ' << t;
        counts << ' ' << c.count;
    }
    h << "\nSIZE" << sizes.str() << "\nTYPE" << types.str() << "\nCOUNT" << counts.str() << "\nWIDTH " << n
      << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << n << "\nDATA " << data << "\n";
    auto value = [&](const Column& c, size_t i, int k) {
        if (k == 0) return c.values[i];
        const bool is_float = c.type == ScalarType::Float32 || c.type == ScalarType::Float64;
        return is_float ? c.values[i] + 1000.0 * k : static_cast<double>(k);  // decoys, in the type's range
    };
    std::string body;
    if (data == "ascii")
    {
        std::ostringstream t;
        for (size_t i = 0; i < n; ++i)
        {
            for (const auto& c : cols)
                for (int k = 0; k < c.count; ++k)
                {
                    appendText(t, value(c, i, k), c.type);
                    t << ' ';
                }
            t << '\n';
        }
        body = t.str();
    }
    else if (data == "binary")
    {
        for (size_t i = 0; i < n; ++i)
            for (const auto& c : cols)
                for (int k = 0; k < c.count; ++k) appendBinary(body, value(c, i, k), c.type, false);
    }
    else
    {
        std::string planar;  // field after field
        for (const auto& c : cols)
            for (size_t i = 0; i < n; ++i)
                for (int k = 0; k < c.count; ++k) appendBinary(planar, value(c, i, k), c.type, false);
        auto packed = lzfCompress(reinterpret_cast<const uint8_t*>(planar.data()), planar.size());
        if (corrupt_lzf && !packed.empty()) packed[0] = 0x20;  // a back reference before any output
        appendBinary(body, static_cast<double>(packed.size()), ScalarType::UInt32, false);
        appendBinary(body, static_cast<double>(planar.size()), ScalarType::UInt32, false);
        body.append(reinterpret_cast<const char*>(packed.data()), packed.size());
    }
    std::string all = h.str() + body;
    all.resize(all.size() - std::min(truncate_bytes, all.size()));
    std::ofstream(path, std::ios::binary) << all;
}

/** Random column values representable in `type` (integers for integer types). */
inline std::vector<double> randomValues(size_t n, ScalarType type, double lo, double hi, std::mt19937& rng)
{
    std::uniform_real_distribution<double> U(lo, hi);
    std::vector<double> v(n);
    for (auto& x : v)
    {
        x = U(rng);
        if (type == ScalarType::Float32)
            x = static_cast<float>(x);
        else if (type != ScalarType::Float64)
            x = std::round(x);
    }
    return v;
}

/** Runs `fn`, expects a core::InputError whose message names `path` and contains `fragment`. */
template <class Fn>
void expectInputError(Fn&& fn, const std::string& path, const std::string& fragment)
{
    try
    {
        fn();
        ADD_FAILURE() << "no InputError thrown (expected one about '" << fragment << "' for " << path << ")";
    }
    catch (const core::InputError& e)
    {
        const std::string msg = e.what();
        EXPECT_NE(msg.find(path), std::string::npos) << "message does not name the file: " << msg;
        EXPECT_NE(msg.find(fragment), std::string::npos) << "message lacks '" << fragment << "': " << msg;
    }
}

}  // namespace quasiloc::map::test
