#pragma once
// Writing a LidarMap as an interchange point cloud (to look at it in CloudCompare & co., or to feed it
// back to map-import): PLY and PCD with float32 x y z intensity (intensity = reflectivity in [0, 1]),
// KITTI .bin, or "x y z i" text. Files are written atomically (temporary + rename).
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/map/map_import.h>
#include <string>

namespace quasiloc::map
{
enum class CloudEncoding
{
    Ascii,
    Binary,           ///< PLY: binary_little_endian; PCD: binary
    BinaryBigEndian,  ///< PLY only
    BinaryCompressed  ///< PCD only (LZF)
};

/** "ascii" "binary" (also "binary_little_endian") "binary_big_endian" "binary_compressed". */
CloudEncoding cloudEncodingFromString(const std::string& name, const std::string& input);
std::string toString(CloudEncoding e);

/** InputError naming `input` if `format` has no such encoding (PLY: no binary_compressed; PCD: no
 *  binary_big_endian; the encoding is ignored for KITTI .bin and text). */
void requireEncodingSupported(CloudFormat format, CloudEncoding encoding, const std::string& input);

/** Writes `map` to `path` in `format` (Auto: from the extension). The encoding applies to PLY and PCD;
 *  InputError for an encoding the format does not have. */
void exportCloud(const LidarMap& map, const std::string& path, CloudFormat format = CloudFormat::Auto,
                 CloudEncoding encoding = CloudEncoding::Binary);

}  // namespace quasiloc::map
