#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <quasiloc/core/error.h>
#include <quasiloc/map/map_import.h>

#include "file_bytes.h"

namespace quasiloc::map
{
namespace detail
{
std::vector<uint8_t> readFileBytes(const std::string& path)
{
    namespace fs = std::filesystem;
    core::require(fs::exists(path), path, "file not found");
    core::require(fs::is_regular_file(path), path, "is not a regular file");
    std::ifstream in(path, std::ios::binary);
    core::require(in.good(), path, "cannot be opened for reading");
    std::vector<uint8_t> bytes(fs::file_size(path));
    in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    core::require(static_cast<size_t>(in.gcount()) == bytes.size(), path, "read error");
    return bytes;
}

std::string lowerCase(std::string s)
{
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

std::vector<std::string> splitWords(std::string_view line)
{
    std::vector<std::string> words;
    size_t i = 0;
    while (i < line.size())
    {
        while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
        size_t j = i;
        while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
        if (j > i) words.emplace_back(line.substr(i, j - i));
        i = j;
    }
    return words;
}

bool parseNumber(std::string_view token, double& value)
{
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    if (token.empty()) return false;
    const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    return ec == std::errc() && ptr == token.data() + token.size();
}

bool TokenCursor::next(std::string_view& token)
{
    while (p_ < end_ && std::isspace(*p_)) ++p_;
    if (p_ == end_) return false;
    const uint8_t* start = p_;
    while (p_ < end_ && !std::isspace(*p_)) ++p_;
    token = std::string_view(reinterpret_cast<const char*>(start), static_cast<size_t>(p_ - start));
    return true;
}

double TokenCursor::number(const std::string& path, const char* element, size_t index)
{
    std::string_view token;
    if (!next(token))
        throw core::InputError(
            path, "data ends early (truncated) while reading " + std::string(element) + " #" + std::to_string(index));
    double v = 0;
    if (!parseNumber(token, v))
        throw core::InputError(
            path, "'" + std::string(token) + "' is not a number (" + element + " #" + std::to_string(index) + ")");
    return v;
}

}  // namespace detail

CloudFormat cloudFormatFromString(const std::string& name, const std::string& input)
{
    const std::string n = detail::lowerCase(name);
    if (n == "auto" || n.empty()) return CloudFormat::Auto;
    if (n == "ply") return CloudFormat::Ply;
    if (n == "pcd") return CloudFormat::Pcd;
    if (n == "kitti" || n == "bin") return CloudFormat::KittiBin;
    if (n == "xyzi" || n == "txt" || n == "text") return CloudFormat::Xyzi;
    throw core::InputError(input, "unknown cloud format '" + name + "' (expected auto, ply, pcd, kitti or xyzi)");
}

std::string toString(CloudFormat f)
{
    switch (f)
    {
        case CloudFormat::Auto: return "auto";
        case CloudFormat::Ply: return "ply";
        case CloudFormat::Pcd: return "pcd";
        case CloudFormat::KittiBin: return "kitti";
        case CloudFormat::Xyzi: return "xyzi";
    }
    return "?";
}

CloudFormat detectCloudFormat(const std::string& path)
{
    const std::string ext = detail::lowerCase(std::filesystem::path(path).extension().string());
    if (ext == ".ply") return CloudFormat::Ply;
    if (ext == ".pcd") return CloudFormat::Pcd;
    if (ext == ".bin") return CloudFormat::KittiBin;
    if (ext == ".txt" || ext == ".xyz" || ext == ".xyzi" || ext == ".csv" || ext == ".asc") return CloudFormat::Xyzi;
    throw core::InputError(path, "unknown point cloud format (extension '" + ext +
                                     "'; expected .ply, .pcd, .bin (KITTI), .txt/.xyz/.xyzi/.csv/.asc "
                                     "(x y z i text), or give the format explicitly)");
}

int intensityFieldRank(const std::string& name)
{
    std::string n = detail::lowerCase(name);
    std::replace(n.begin(), n.end(), ' ', '_');
    if (n == "intensity") return 1;
    if (n == "reflectivity") return 2;
    if (n == "reflectance") return 3;
    if (n == "scalar_intensity") return 4;
    if (n == "scalar_reflectivity" || n == "scalar_reflectance") return 5;
    if (n == "scalar_field" || n == "scalarfield" || n == "scalar_scalar_field" || n == "scalar_scalarfield") return 6;
    if (n.rfind("scalar_", 0) == 0 && n.size() > 7) return 7;
    if (n == "i") return 8;
    return 0;
}

int timeFieldRank(const std::string& name)
{
    const std::string n = detail::lowerCase(name);
    if (n == "time") return 1;
    if (n == "t") return 2;
    if (n == "offset_time") return 3;
    if (n == "timestamp") return 4;
    return 0;
}

bool isRingField(const std::string& name)
{
    const std::string n = detail::lowerCase(name);
    return n == "ring" || n == "line" || n == "laser_id";
}

void RawCloud::reserve(size_t n)
{
    x.reserve(n);
    y.reserve(n);
    z.reserve(n);
    intensity.reserve(n);
}

RawCloud readCloud(const std::string& path, CloudFormat format)
{
    if (format == CloudFormat::Auto) format = detectCloudFormat(path);
    return readCloudBytes(detail::readFileBytes(path), format, path);
}

RawCloud readCloudBytes(const std::vector<uint8_t>& bytes, CloudFormat format, const std::string& path)
{
    RawCloud cloud;
    switch (format)
    {
        case CloudFormat::Ply: cloud = detail::parsePly(bytes, path); break;
        case CloudFormat::Pcd: cloud = detail::parsePcd(bytes, path); break;
        case CloudFormat::KittiBin: cloud = detail::parseKittiBin(bytes, path); break;
        case CloudFormat::Xyzi: cloud = detail::parseXyziText(bytes, path); break;
        case CloudFormat::Auto: throw core::InputError(path, "readCloudBytes needs an explicit cloud format");
    }
    core::require(cloud.size() > 0, path, "the cloud is empty (no points)");
    for (size_t i = 0; i < cloud.size(); ++i)
    {
        if (!std::isfinite(cloud.x[i]) || !std::isfinite(cloud.y[i]) || !std::isfinite(cloud.z[i]))
            throw core::InputError(path, "point " + std::to_string(i) + " has a non-finite (NaN or inf) coordinate");
        if (!std::isfinite(cloud.intensity[i]))
            throw core::InputError(path, "point " + std::to_string(i) + " has a non-finite intensity");
        if (!cloud.time.empty() && !std::isfinite(cloud.time[i]))
            throw core::InputError(path, "point " + std::to_string(i) + " has a non-finite time");
    }
    return cloud;
}

}  // namespace quasiloc::map
