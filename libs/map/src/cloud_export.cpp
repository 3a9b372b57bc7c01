#include <cstring>
#include <fstream>
#include <iomanip>
#include <quasiloc/core/error.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/map/cloud_export.h>
#include <quasiloc/map/lzf.h>
#include <sstream>

#include "file_bytes.h"
#include "scalar_types.h"

namespace quasiloc::map
{
namespace
{
using detail::ScalarType;

/** The 4 float channels as little- or big-endian bytes, point after point (interleaved) or channel
 *  after channel (planar, the layout PCD binary_compressed compresses). */
std::vector<uint8_t> packFloats(const LidarMap& map, bool big_endian, bool planar)
{
    const size_t n = map.size();
    const float* C[4] = {map.xs(), map.ys(), map.zs(), map.reflectivities()};
    const bool swap = big_endian != detail::hostIsBigEndian();
    std::vector<uint8_t> out(16 * n);
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 4; ++c)
        {
            const size_t at = planar ? (c * n + i) * 4 : (i * 4 + c) * 4;
            detail::encodeScalar(C[c][i], ScalarType::Float32, swap, &out[at]);
        }
    return out;
}

std::string asciiRows(const LidarMap& map)
{
    std::ostringstream s;
    s << std::setprecision(9);
    for (size_t i = 0; i < map.size(); ++i)
        s << map.xs()[i] << ' ' << map.ys()[i] << ' ' << map.zs()[i] << ' ' << map.reflectivities()[i] << '\n';
    return s.str();
}

std::string plyHeader(size_t n, CloudEncoding e)
{
    std::ostringstream s;
    s << "ply\nformat "
      << (e == CloudEncoding::Ascii    ? "ascii"
          : e == CloudEncoding::Binary ? "binary_little_endian"
                                       : "binary_big_endian")
      << " 1.0\ncomment quasiloc LidarMap, intensity = reflectivity in [0, 1]\nelement vertex " << n
      << "\nproperty float x\nproperty float y\nproperty float z\nproperty float intensity\nend_header\n";
    return s.str();
}

std::string pcdHeader(size_t n, CloudEncoding e)
{
    std::ostringstream s;
    s << "# .PCD v0.7 - Point Cloud Data file format (quasiloc LidarMap, intensity = reflectivity)\n"
      << "VERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\nWIDTH " << n
      << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << n << "\nDATA "
      << (e == CloudEncoding::Ascii    ? "ascii"
          : e == CloudEncoding::Binary ? "binary"
                                       : "binary_compressed")
      << "\n";
    return s.str();
}

void writeAll(const std::string& tmp, const std::string& path, const std::string& head, const uint8_t* data,
              size_t size)
{
    std::ofstream f(tmp, std::ios::binary);
    core::require(f.good(), path, "cannot open for writing");
    f.write(head.data(), static_cast<std::streamsize>(head.size()));
    f.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    f.close();
    core::require(!f.fail(), path, "write failed");
}

std::vector<uint8_t> pcdCompressedBlock(const LidarMap& map)
{
    const std::vector<uint8_t> planar = packFloats(map, false, true);
    const std::vector<uint8_t> packed = lzfCompress(planar.data(), planar.size());
    std::vector<uint8_t> block(8 + packed.size());
    detail::encodeScalar(static_cast<double>(packed.size()), ScalarType::UInt32, detail::hostIsBigEndian(), &block[0]);
    detail::encodeScalar(static_cast<double>(planar.size()), ScalarType::UInt32, detail::hostIsBigEndian(), &block[4]);
    std::memcpy(block.data() + 8, packed.data(), packed.size());
    return block;
}
}  // namespace

CloudEncoding cloudEncodingFromString(const std::string& name, const std::string& input)
{
    const std::string n = detail::lowerCase(name);
    if (n == "ascii") return CloudEncoding::Ascii;
    if (n == "binary" || n == "binary_little_endian") return CloudEncoding::Binary;
    if (n == "binary_big_endian") return CloudEncoding::BinaryBigEndian;
    if (n == "binary_compressed") return CloudEncoding::BinaryCompressed;
    throw core::InputError(
        input, "unknown encoding '" + name + "' (expected ascii, binary, binary_big_endian or binary_compressed)");
}

std::string toString(CloudEncoding e)
{
    switch (e)
    {
        case CloudEncoding::Ascii: return "ascii";
        case CloudEncoding::Binary: return "binary";
        case CloudEncoding::BinaryBigEndian: return "binary_big_endian";
        case CloudEncoding::BinaryCompressed: return "binary_compressed";
    }
    return "?";
}

void requireEncodingSupported(CloudFormat format, CloudEncoding encoding, const std::string& input)
{
    core::require(!(format == CloudFormat::Ply && encoding == CloudEncoding::BinaryCompressed), input,
                  "PLY has no binary_compressed encoding (ascii, binary, binary_big_endian)");
    core::require(!(format == CloudFormat::Pcd && encoding == CloudEncoding::BinaryBigEndian), input,
                  "PCD has no big-endian encoding (ascii, binary, binary_compressed)");
}

void exportCloud(const LidarMap& map, const std::string& path, CloudFormat format, CloudEncoding encoding)
{
    if (format == CloudFormat::Auto) format = detectCloudFormat(path);
    requireEncodingSupported(format, encoding, path);
    core::StagedOutputs staged;
    const std::string tmp = staged.addFile(path);
    const size_t n = map.size();
    switch (format)
    {
        case CloudFormat::Ply:
        {
            if (encoding == CloudEncoding::Ascii)
            {
                const std::string rows = asciiRows(map);
                writeAll(tmp, path, plyHeader(n, encoding), reinterpret_cast<const uint8_t*>(rows.data()), rows.size());
            }
            else
            {
                const auto data = packFloats(map, encoding == CloudEncoding::BinaryBigEndian, false);
                writeAll(tmp, path, plyHeader(n, encoding), data.data(), data.size());
            }
            break;
        }
        case CloudFormat::Pcd:
        {
            std::vector<uint8_t> data;
            if (encoding == CloudEncoding::Ascii)
            {
                const std::string rows = asciiRows(map);
                data.assign(rows.begin(), rows.end());
            }
            else if (encoding == CloudEncoding::Binary)
                data = packFloats(map, false, false);
            else
                data = pcdCompressedBlock(map);
            writeAll(tmp, path, pcdHeader(n, encoding), data.data(), data.size());
            break;
        }
        case CloudFormat::KittiBin:
        {
            const auto data = packFloats(map, false, false);
            writeAll(tmp, path, "", data.data(), data.size());
            break;
        }
        case CloudFormat::Xyzi:
        {
            const std::string rows = "# x y z reflectivity\n" + asciiRows(map);
            writeAll(tmp, path, "", reinterpret_cast<const uint8_t*>(rows.data()), rows.size());
            break;
        }
        case CloudFormat::Auto: break;
    }
    staged.commit();
}

}  // namespace quasiloc::map
