#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <mrpt/core/exceptions.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/serialization/CArchive.h>
#include <quasiloc/core/error.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/map/lidar_map.h>
#include <sstream>

namespace quasiloc::map
{
LidarMap::LidarMap() : points_(std::make_shared<mrpt::maps::CPointsMapXYZI>()) {}

LidarMap::LidarMap(mrpt::maps::CPointsMapXYZI::Ptr points) : points_(std::move(points))
{
    if (!points_) points_ = std::make_shared<mrpt::maps::CPointsMapXYZI>();
}

void LidarMap::reserve(size_t n) { points_->reserve(n); }

void LidarMap::addPoint(float x, float y, float z, float reflectivity)
{
    // insertPointRGB stores R as the intensity (G, B are ignored by CPointsMapXYZI).
    points_->insertPointRGB(x, y, z, reflectivity, 0, 0);
}

MapBounds LidarMap::bounds() const
{
    MapBounds b;
    const size_t n = size();
    if (n == 0) return b;
    const float* P[3] = {xs(), ys(), zs()};
    for (int a = 0; a < 3; ++a)
    {
        float lo = P[a][0], hi = P[a][0];
        for (size_t i = 1; i < n; ++i)
        {
            lo = std::min(lo, P[a][i]);
            hi = std::max(hi, P[a][i]);
        }
        b.min[a] = lo;
        b.max[a] = hi;
    }
    return b;
}

std::pair<float, float> LidarMap::reflectivityRange() const
{
    const size_t n = size();
    if (n == 0) return {0.f, 0.f};
    const float* r = reflectivities();
    float lo = r[0], hi = r[0];
    for (size_t i = 1; i < n; ++i)
    {
        lo = std::min(lo, r[i]);
        hi = std::max(hi, r[i]);
    }
    return {lo, hi};
}

void LidarMap::check(const std::string& input) const
{
    core::require(!empty(), input, "the map is empty (no points)");
    core::require(points_->getPointsBufferRef_intensity().size() == size(), input,
                  "the intensity channel does not have one value per point");
    const float* P[4] = {xs(), ys(), zs(), reflectivities()};
    for (size_t i = 0; i < size(); ++i)
    {
        if (!std::isfinite(P[0][i]) || !std::isfinite(P[1][i]) || !std::isfinite(P[2][i]))
            throw core::InputError(input, "point " + std::to_string(i) + " has a non-finite (NaN or inf) coordinate");
        if (!(P[3][i] >= 0.f && P[3][i] <= 1.f))
            throw core::InputError(input, "point " + std::to_string(i) + " has reflectivity " +
                                              std::to_string(P[3][i]) + " outside [0, 1]");
    }
}

void LidarMap::save(const std::string& path) const
{
    core::StagedOutputs staged;
    const std::string tmp = staged.addFile(path);
    {
        mrpt::io::CFileGZOutputStream out;
        std::string err;
        core::require(out.open(tmp, 1, err), path, "cannot open for writing: " + err);
        try
        {
            mrpt::serialization::archiveFrom(out) << *points_;
        }
        catch (const std::exception& e)
        {
            throw core::InputError(path, "write failed: " + mrpt::exception_to_str(e));
        }
        out.close();
    }
    staged.commit();
}

namespace
{
const char* const kNotAMap = "cannot be read as a serialized MRPT map (not a map file, or truncated): ";
const std::string kPointsClass = "mrpt::maps::CPointsMapXYZI";

/** Checks the archive's object header and point count before MRPT reads it: CPointsMapXYZI::serializeFrom resizes
 *  its arrays to the count it reads, so a corrupt count allocated up to 64 GB (found by fuzz_lidar_map). Layout
 *  (MRPT 2): 0x80 | name length, the class name, a version byte, uint32 n, then n floats of x, y, z and intensity.
 *  Reads at most the point data (a second pass over the file, stopped once the points are known to be there). */
void checkMapArchive(const std::string& path)
{
    mrpt::io::CFileGZInputStream in;
    core::require(in.open(path), path, "cannot open the map file for reading");
    uint8_t name_length = 0;
    core::require(in.Read(&name_length, 1) == 1 && (name_length & 0x80) != 0, path,
                  std::string(kNotAMap) + "no MRPT object header");
    std::string name(name_length & 0x7f, '\0');
    core::require(in.Read(name.data(), name.size()) == name.size(), path, std::string(kNotAMap) + "header cut short");
    core::require(name == kPointsClass, path, "the file holds a " + name + ", expected a " + kPointsClass);
    uint8_t version = 0;
    uint8_t count_bytes[4] = {};
    core::require(in.Read(&version, 1) == 1 && in.Read(count_bytes, 4) == 4, path,
                  std::string(kNotAMap) + "header cut short");
    const uint64_t n = uint64_t(count_bytes[0]) | uint64_t(count_bytes[1]) << 8 | uint64_t(count_bytes[2]) << 16 |
                       uint64_t(count_bytes[3]) << 24;
    const uint64_t need = 16 * n;  // x, y, z, intensity: float32 each
    uint64_t have = 0;
    std::vector<char> buf(1 << 16);
    while (have < need)
    {
        const size_t got = in.Read(buf.data(), static_cast<size_t>(std::min<uint64_t>(buf.size(), need - have)));
        if (got == 0) break;
        have += got;
    }
    core::require(have >= need, path,
                  std::string(kNotAMap) + std::to_string(n) + " points announced, but the file ends after " +
                      std::to_string(have) + " bytes of the " + std::to_string(need) + " they need");
}
}  // namespace

LidarMap LidarMap::load(const std::string& path)
{
    core::require(std::filesystem::exists(path), path, "map file not found");
    core::require(std::filesystem::is_regular_file(path), path, "is not a regular file");
    checkMapArchive(path);
    mrpt::io::CFileGZInputStream in;
    core::require(in.open(path), path, "cannot open the map file for reading");
    mrpt::serialization::CSerializable::Ptr obj;
    try
    {
        obj = mrpt::serialization::archiveFrom(in).ReadObject();
    }
    catch (const std::exception& e)
    {
        throw core::InputError(path, kNotAMap + mrpt::exception_to_str(e));
    }
    core::require(obj != nullptr, path, "the file holds a null object, expected a mrpt::maps::CPointsMapXYZI");
    auto points = std::dynamic_pointer_cast<mrpt::maps::CPointsMapXYZI>(obj);
    core::require(points != nullptr, path,
                  std::string("the file holds a ") + obj->GetRuntimeClass()->className +
                      ", expected a mrpt::maps::CPointsMapXYZI");
    LidarMap map(points);
    map.check(path);
    return map;
}

std::string LidarMap::summary() const
{
    std::ostringstream s;
    s << size() << " points";
    if (empty()) return s.str();
    const MapBounds b = bounds();
    const auto [rlo, rhi] = reflectivityRange();
    s << std::fixed << std::setprecision(2) << ", bounds [" << b.min.x() << " " << b.min.y() << " " << b.min.z()
      << "]..[" << b.max.x() << " " << b.max.y() << " " << b.max.z() << "] m" << std::setprecision(3)
      << ", reflectivity [" << rlo << ", " << rhi << "]";
    return s.str();
}

}  // namespace quasiloc::map
