#pragma once
// LiDAR scans as map-build reads them, one at a time: the points in the LiDAR's own frame with their raw
// intensities and, where the scan carries them, per-point times (for deskewing) and ring numbers (for the per-ring
// reflectivity gain). A ScanSource hands out scans by index so that a map is built from any number of scans with
// one scan in memory at a time, and so that a pass can read them again (map_build.h reads every scan two or three
// times rather than keep any).
//
// Sources: FolderScanSource (a folder of KITTI .bin, PCD or PLY files, one scan per file, in file-name order), and
// ros::BagScanSource (libs/ros bag_scan_source.h: the PointCloud2 messages of one topic of a ROS 1 or ROS 2 bag, which
// it reads front to back in one pass per forEach).
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <memory>
#include <quasiloc/map/map_import.h>
#include <string>
#include <vector>

namespace quasiloc::map
{
struct LidarScan
{
    std::string name;                     ///< the file (or message) it came from: errors name it
    std::vector<Eigen::Vector3f> points;  ///< in the LiDAR frame, metres
    std::vector<float> intensity;         ///< raw, as stored
    std::vector<double> time_s;           ///< per point, seconds (after the scan's stamp, or absolute: time_absolute);
                                          ///< empty: none stored
    bool time_absolute = false;           ///< time_s holds absolute times (a "timestamp" field), not offsets
    std::vector<uint16_t> ring;           ///< per point laser index; empty: none stored or estimated
    size_t invalid_points = 0;            ///< points without a position (NaN in organised clouds), dropped
    size_t size() const { return points.size(); }
};

/** Where a scan's ring numbers come from. */
enum class RingSource
{
    None,         ///< no per-ring gain
    Field,        ///< the scan's own ring field (PCD/PLY "ring"); scans without one get none
    AzimuthWrap,  ///< a new ring each time the azimuth jumps back by more than pi (scans stored laser by laser,
                  ///< as KITTI's .bin: checked on kitti_raw_seq78, 64 wraps per HDL-64 scan)
};

/** Ring numbers by azimuth wraps (see RingSource::AzimuthWrap), in the scan's point order. */
std::vector<uint16_t> ringsFromAzimuthWraps(const std::vector<Eigen::Vector3f>& points);

/** A scan from a cloud file read by the map importers (readCloud): x y z, the raw intensity, and the per-point
 *  time and ring where the cloud has such fields. Times are converted to seconds by the field's convention
 *  (timeFieldRank in map_import.h): time in s, t and offset_time in ns, timestamp in absolute s. */
LidarScan scanFromCloud(RawCloud&& cloud, const std::string& name);

class ScanSource
{
   public:
    virtual ~ScanSource() = default;
    virtual size_t size() const = 0;
    /** The scan's name (its file), without reading it. */
    virtual std::string name(size_t i) const = 0;
    /** Reads scan i. InputError naming the scan when it does not parse, is empty or holds a non-finite value. */
    virtual LidarScan read(size_t i) const = 0;
    /** Reads every scan in index order, one at a time: visit(i, scan). This default calls read(i) for each; a source
     *  that can only be read front to back (a bag) reads it once. */
    virtual void forEach(const std::function<void(size_t, LidarScan&&)>& visit) const;
};

/** The files of `folder` with the format's extension (Auto: every .bin .pcd .ply; one format per folder), sorted by
 *  name. InputError for a missing folder, no scan files, or (Auto) files of more than one format. */
class FolderScanSource : public ScanSource
{
   public:
    FolderScanSource(const std::string& folder, CloudFormat format);
    size_t size() const override { return files_.size(); }
    std::string name(size_t i) const override { return files_[i]; }
    LidarScan read(size_t i) const override;
    CloudFormat format() const { return format_; }

   private:
    std::vector<std::string> files_;
    CloudFormat format_;
};

}  // namespace quasiloc::map
