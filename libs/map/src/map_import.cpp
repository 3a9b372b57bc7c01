// Reflectivity normalisation and the import pipeline (read -> normalise -> voxel downsample).
#include <algorithm>
#include <cmath>
#include <mrpt/system/CTimeLogger.h>
#include <optional>
#include <quasiloc/core/error.h>
#include <quasiloc/map/map_import.h>
#include <sstream>

namespace quasiloc::map
{
namespace
{
std::string num(double v)
{
    std::ostringstream s;
    s << v;
    return s.str();
}
}  // namespace

IntensityNormalisation chooseIntensityNormalisation(const std::vector<float>& raw, double intensity_scale,
                                                    const std::string& input)
{
    core::require(std::isfinite(intensity_scale) && intensity_scale >= 0, input,
                  "must be >= 0 (0 = automatic rule), got " + num(intensity_scale));
    IntensityNormalisation n;
    if (!raw.empty())
    {
        const auto [lo, hi] = std::minmax_element(raw.begin(), raw.end());
        n.raw_min = *lo;
        n.raw_max = *hi;
    }
    const std::string range = "raw range [" + num(n.raw_min) + ", " + num(n.raw_max) + "]";
    if (intensity_scale > 0)
    {
        n.divisor = intensity_scale;
        n.rule = "divided by intensity_scale = " + num(intensity_scale) + " (given; " + range + ")";
    }
    else if (n.raw_min >= 0 && n.raw_max <= 1)
    {
        n.divisor = 1;
        n.rule = "kept as is (automatic: all raw values within [0, 1]; " + range + ")";
    }
    else if (n.raw_max <= 255)
    {
        n.divisor = 255;
        n.rule = "divided by 255 (automatic: raw maximum <= 255; " + range + ")";
    }
    else if (n.raw_max <= 65535)
    {
        n.divisor = 65535;
        n.rule = "divided by 65535 (automatic: raw maximum <= 65535; " + range + ")";
    }
    else
    {
        n.divisor = n.raw_max;
        n.rule = "divided by the maximum " + num(n.raw_max) + " (automatic: raw maximum > 65535; " + range + ")";
    }
    return n;
}

LidarMap toLidarMap(const RawCloud& cloud, IntensityNormalisation& norm)
{
    LidarMap map;
    map.reserve(cloud.size());
    const double inv = 1.0 / norm.divisor;
    norm.clamped = 0;
    for (size_t i = 0; i < cloud.size(); ++i)
    {
        double r = cloud.intensity[i] * inv;
        if (r < 0 || r > 1)
        {
            r = std::clamp(r, 0.0, 1.0);
            ++norm.clamped;
        }
        map.addPoint(cloud.x[i], cloud.y[i], cloud.z[i], static_cast<float>(r));
    }
    return map;
}

ImportResult importCloud(const std::string& path, const ImportOptions& options, mrpt::system::CTimeLogger* timer)
{
    core::require(options.voxel_size_m >= 0 && std::isfinite(options.voxel_size_m), "voxel_size_m",
                  "must be >= 0 (0 = no downsampling), got " + num(options.voxel_size_m));
    // Times a stage if a logger was given (leaves the section also when the stage throws).
    auto stage = [timer](const char* name) {
        return timer ? std::make_optional<mrpt::system::CTimeLoggerEntry>(*timer, name) : std::nullopt;
    };
    ImportResult result;
    result.format = options.format == CloudFormat::Auto ? detectCloudFormat(path) : options.format;
    RawCloud cloud;
    {
        const auto t = stage("import.read");
        cloud = readCloud(path, result.format);
    }
    result.points_read = cloud.size();
    result.encoding = cloud.encoding;
    result.intensity_field = cloud.intensity_field;
    {
        const auto t = stage("import.normalise");
        result.normalisation = chooseIntensityNormalisation(cloud.intensity, options.intensity_scale);
        result.map = toLidarMap(cloud, result.normalisation);
        cloud = RawCloud();  // free the raw copy before downsampling
    }
    if (options.voxel_size_m > 0)
    {
        const auto t = stage("import.voxel");
        result.map = voxelDownsample(result.map, options.voxel_size_m);
    }
    return result;
}

}  // namespace quasiloc::map
