#include <algorithm>
#include <cmath>
#include <filesystem>
#include <quasiloc/core/error.h>
#include <quasiloc/map/lidar_scan.h>

#include "file_bytes.h"

namespace quasiloc::map
{
std::vector<uint16_t> ringsFromAzimuthWraps(const std::vector<Eigen::Vector3f>& points)
{
    std::vector<uint16_t> ring(points.size(), 0);
    uint16_t r = 0;
    float previous = 0;
    for (size_t i = 0; i < points.size(); ++i)
    {
        const float azimuth = std::atan2(points[i].y(), points[i].x());
        if (i > 0 && azimuth - previous < -float(M_PI) && r < UINT16_MAX) ++r;
        previous = azimuth;
        ring[i] = r;
    }
    return ring;
}

LidarScan scanFromCloud(RawCloud&& cloud, const std::string& name)
{
    LidarScan scan;
    scan.name = name;
    scan.points.resize(cloud.size());
    for (size_t i = 0; i < cloud.size(); ++i) scan.points[i] = {cloud.x[i], cloud.y[i], cloud.z[i]};
    scan.intensity = std::move(cloud.intensity);
    scan.ring = std::move(cloud.ring);
    if (!cloud.time.empty())
    {
        const int rank = timeFieldRank(cloud.time_field);
        const double scale = rank == 2 || rank == 3 ? 1e-9 : 1.0;
        scan.time_absolute = rank == 4;
        scan.time_s = std::move(cloud.time);
        for (double& t : scan.time_s) t *= scale;
    }
    return scan;
}

FolderScanSource::FolderScanSource(const std::string& folder, CloudFormat format) : format_(format)
{
    namespace fs = std::filesystem;
    core::require(fs::is_directory(folder), folder, "is not a folder of scans");
    std::vector<std::string> exts;
    if (format == CloudFormat::Auto)
        exts = {".bin", ".pcd", ".ply"};
    else
        exts = {format == CloudFormat::KittiBin ? ".bin" : format == CloudFormat::Pcd ? ".pcd" : ".ply"};
    core::require(format == CloudFormat::Auto || format == CloudFormat::KittiBin || format == CloudFormat::Pcd ||
                      format == CloudFormat::Ply,
                  folder, "scans must be KITTI .bin, PCD or PLY files");
    for (const auto& entry : fs::directory_iterator(folder))
    {
        if (!entry.is_regular_file()) continue;
        const std::string ext = detail::lowerCase(entry.path().extension().string());
        if (std::find(exts.begin(), exts.end(), ext) != exts.end()) files_.push_back(entry.path().string());
    }
    std::sort(files_.begin(), files_.end());
    core::require(!files_.empty(), folder, "holds no scan file (" + toString(format) + ": .bin, .pcd or .ply)");
    if (format_ == CloudFormat::Auto)
    {
        format_ = detectCloudFormat(files_.front());
        for (const std::string& f : files_)
            core::require(detectCloudFormat(f) == format_, folder,
                          "holds scans of more than one format (" + files_.front() + ", " + f + "): set scan_format");
    }
}

void ScanSource::forEach(const std::function<void(size_t, LidarScan&&)>& visit) const
{
    for (size_t i = 0; i < size(); ++i) visit(i, read(i));
}

LidarScan FolderScanSource::read(size_t i) const { return scanFromCloud(readCloud(files_.at(i), format_), files_[i]); }

}  // namespace quasiloc::map
