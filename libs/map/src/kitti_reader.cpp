// KITTI velodyne scans: a headerless array of float32 little-endian records (x, y, z, reflectance).
#include <quasiloc/core/error.h>
#include <quasiloc/map/map_import.h>

#include "file_bytes.h"
#include "scalar_types.h"

namespace quasiloc::map
{
RawCloud readKittiBin(const std::string& path) { return detail::parseKittiBin(detail::readFileBytes(path), path); }

RawCloud detail::parseKittiBin(const std::vector<uint8_t>& bytes, const std::string& path)
{
    core::require(bytes.size() % 16 == 0, path,
                  "truncated KITTI .bin: " + std::to_string(bytes.size()) +
                      " bytes is not a whole number of 16-byte (x y z r float32) records");
    const size_t n = bytes.size() / 16;
    const bool swap = detail::hostIsBigEndian();
    RawCloud cloud;
    cloud.encoding = "float32 x y z r";
    cloud.intensity_field = "r";
    cloud.reserve(n);
    for (size_t i = 0; i < n; ++i)
    {
        float v[4];
        for (int k = 0; k < 4; ++k)
            v[k] = static_cast<float>(detail::decodeScalar(&bytes[16 * i + 4 * k], detail::ScalarType::Float32, swap));
        cloud.push(v[0], v[1], v[2], v[3]);
    }
    return cloud;
}

}  // namespace quasiloc::map
