#pragma once
// Importing point clouds with reflectivity into a LidarMap.
//
// Readers (our own parsers, no PCL):
//  - PLY  (.ply): ascii, binary_little_endian, binary_big_endian. The "vertex" element must have x, y, z
//    and an intensity-like property (see intensityFieldRank); any numeric type (char uchar short ushort
//    int uint float double and the int8 ... float64 aliases). Other properties (also lists) and other
//    elements are skipped.
//  - PCD  (.pcd): v0.7 header, DATA ascii | binary | binary_compressed (LZF), fields x y z and
//    intensity | reflectivity | i (or the other intensity-like names), any SIZE/TYPE/COUNT (the first
//    element of a field with COUNT > 1 is used).
//  - KITTI velodyne (.bin): float32 little-endian records x y z r.
//  - XYZI text (.txt .xyz .xyzi .csv .asc): "x y z i" per line, separated by spaces, tabs or commas;
//    '#' starts a comment; blank lines are skipped; any other column count is an error.
// Bad input (missing file, unknown format, no intensity field, non-finite coordinates or intensities,
// empty cloud, truncated data, malformed header) throws core::InputError naming the file and the problem.
// Non-finite coordinates are rejected, not skipped: this includes the NaN placeholders of organised PCDs
// (filter those out before importing, so that nothing is dropped silently).
//
// Reflectivity normalisation (raw intensity -> reflectivity in [0, 1]):
//  - intensity_scale > 0: reflectivity = raw / intensity_scale (intensity_scale is the raw value that
//    means full reflectivity, e.g. 255 for 8-bit intensities; 1 keeps the values);
//  - intensity_scale = 0 (automatic): if every raw value is within [0, 1] they are kept; else if the
//    maximum is <= 255 they are divided by 255; else if the maximum is <= 65535 they are divided by
//    65535; else they are divided by the maximum.
//  In both cases a result outside [0, 1] (negative raw values, or values above the given scale) is
//  clamped to [0, 1] and counted in IntensityNormalisation::clamped.
//
// Voxel downsampling (voxel_size_m > 0): the space is cut into cubes of voxel_size_m aligned with the
// world origin; each occupied cube yields one point at the mean position and mean reflectivity of its
// points. Points are grouped by sorting 64-bit voxel keys (O(n log n), ~0.1 s per million points).
#include <mrpt/system/CTimeLogger.h>

#include <cstdint>
#include <quasiloc/map/lidar_map.h>
#include <string>
#include <vector>

namespace quasiloc::map
{
enum class CloudFormat
{
    Auto,  ///< from the file extension
    Ply,
    Pcd,
    KittiBin,
    Xyzi
};

/** "auto" "ply" "pcd" "kitti" (also "bin") "xyzi" (also "txt"); InputError naming `input` otherwise. */
CloudFormat cloudFormatFromString(const std::string& name, const std::string& input);
std::string toString(CloudFormat f);
/** The format of `path` from its extension (case-insensitive); InputError for an unknown extension. */
CloudFormat detectCloudFormat(const std::string& path);

/** Priority of a field/property name as the intensity channel (case-insensitive): 1 intensity,
 *  2 reflectivity, 3 reflectance, 4 scalar_intensity, 5 scalar_reflectivity / scalar_reflectance,
 *  6 "scalar field" variants (scalar_field, scalarfield, scalar_scalar_field, ...), 7 any other scalar_*,
 *  8 i; 0 = not intensity-like. The lowest positive rank present wins. */
int intensityFieldRank(const std::string& name);

/** Priority of a field/property name as a per-point time (case-insensitive), for deskewing scans: 1 time
 *  (Velodyne ROS driver: seconds from the scan's stamp), 2 t (Ouster: nanoseconds from the stamp), 3 offset_time
 *  (Livox: nanoseconds from the stamp), 4 timestamp (Hesai, RoboSense: absolute seconds); 0 = not a time. */
int timeFieldRank(const std::string& name);
/** A per-point ring / laser number: ring (Velodyne, Ouster, Hesai), line (Livox), laser_id (case-insensitive). */
bool isRingField(const std::string& name);

/** A cloud as read from a file: coordinates and the raw (not yet normalised) intensity values. */
struct RawCloud
{
    std::vector<float> x, y, z;
    std::vector<float> intensity;
    std::string intensity_field;  ///< the field or property the intensity was read from
    std::vector<double> time;     ///< per point, as stored (units: timeFieldRank); empty: the cloud has no time field
    std::vector<uint16_t> ring;   ///< per point; empty: the cloud has no ring field
    std::string time_field, ring_field;
    std::string encoding;  ///< e.g. "binary_little_endian", "binary_compressed", "ascii"
    size_t size() const { return x.size(); }
    void reserve(size_t n);
    void push(float px, float py, float pz, float pi)
    {
        x.push_back(px);
        y.push_back(py);
        z.push_back(pz);
        intensity.push_back(pi);
    }
};

RawCloud readPly(const std::string& path);
RawCloud readPcd(const std::string& path);
RawCloud readKittiBin(const std::string& path);
RawCloud readXyziText(const std::string& path);
/** Reads with the given format (Auto: from the extension), then checks the cloud is non-empty and every
 *  coordinate and intensity is finite (InputError naming the file and the first bad point). */
RawCloud readCloud(const std::string& path, CloudFormat format = CloudFormat::Auto);
/** readCloud on the bytes of a file (format not Auto); `input` names them in errors. The fuzz targets'
 *  entry point (fuzz/), and the same code path as readCloud. */
RawCloud readCloudBytes(const std::vector<uint8_t>& bytes, CloudFormat format, const std::string& input);

struct IntensityNormalisation
{
    double divisor = 1.0;  ///< reflectivity = clamp(raw / divisor, 0, 1)
    std::string rule;      ///< human-readable: which rule was applied
    float raw_min = 0, raw_max = 0;
    size_t clamped = 0;  ///< values clamped into [0, 1] (filled by normaliseIntensities)
};

/** Chooses the divisor by the rule above (intensity_scale = 0: automatic). InputError naming `input`
 *  for a negative or non-finite intensity_scale. */
IntensityNormalisation chooseIntensityNormalisation(const std::vector<float>& raw, double intensity_scale,
                                                    const std::string& input = "intensity_scale");

/** Builds the LidarMap from a raw cloud with the chosen normalisation (fills `norm.clamped`). */
LidarMap toLidarMap(const RawCloud& cloud, IntensityNormalisation& norm);

/** One point per occupied voxel (mean position, mean reflectivity), in voxel-key order.
 *  voxel_size_m must be > 0; InputError if the cloud spans more than 2^21 voxels along an axis. */
LidarMap voxelDownsample(const LidarMap& map, double voxel_size_m);

struct ImportOptions
{
    CloudFormat format = CloudFormat::Auto;
    double voxel_size_m = 0.0;     ///< 0 = keep every point
    double intensity_scale = 0.0;  ///< 0 = automatic rule
};

struct ImportResult
{
    LidarMap map;
    CloudFormat format = CloudFormat::Auto;  ///< the format actually read
    std::string encoding, intensity_field;
    size_t points_read = 0;
    IntensityNormalisation normalisation;
};

/** read -> normalise -> (voxel downsample). Stages are timed in `timer` if given. */
ImportResult importCloud(const std::string& path, const ImportOptions& options,
                         mrpt::system::CTimeLogger* timer = nullptr);

}  // namespace quasiloc::map
