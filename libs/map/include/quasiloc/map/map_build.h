#pragma once
// map-build: a LidarMap from LiDAR scans and their poses (docs/map-build.md).
//   pass 1: each scan read, put in the world frame (deskewed where it has per-point times), fused into voxels
//           (positions, raw intensities) and into the carving grid (hits, surface moments);
//   pass 2: each scan read again: its rays cast through the carving grid, its raw intensities compared with their
//           voxels' means (the reflectivity model's observations);
//   pass 3: each scan read a third time: reflectivities normalised by the fitted model accumulated in the voxels
//           (only with a ring or range normalisation).
// One scan is in memory at a time; the voxel hashes grow with the occupied volume only. The map holds the voxels'
// mean points, without those in free carving voxels; those are returned as `removed`.
#include <functional>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/map/cloud_export.h>
#include <quasiloc/map/free_space_carving.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/map/lidar_scan.h>
#include <quasiloc/map/scan_fusion.h>
#include <quasiloc/map/scan_poses.h>
#include <string>
#include <vector>

namespace quasiloc::map
{
enum class ScanSourceKind
{
    Folder,  ///< scan_folder: one file per scan
    Bag      ///< bag, bag_lidar_topic: one PointCloud2 message per scan (read by libs/ros BagScanSource)
};

/** Where T_body_lidar comes from. */
enum class ExtrinsicSource
{
    Keys,     ///< T_body_lidar or extrinsic_file (neither: identity)
    TfStatic  ///< the scans' bag's static transforms: body_frame to the PointCloud2 header.frame_id
};

enum class ReflectivityNormalisation
{
    None,
    Range,
    Ring,
    RangeRing
};

/** Section [MapBuild]; each key's unit, range and meaning: declare() (map_build_options.cpp). */
struct MapBuildOptions : public core::DeclaredOptions
{
    ScanSourceKind source = ScanSourceKind::Folder;
    std::string scan_folder;
    CloudFormat scan_format = CloudFormat::Auto;
    std::string bag;
    std::string bag_lidar_topic;
    std::string trajectory;
    TrajectoryFormat trajectory_format = TrajectoryFormat::Tum;
    std::string bag_pose_topic;
    ScanTimeSource scan_times = ScanTimeSource::Auto;
    std::string scan_times_file;
    double scan_time_scale = 1.0;
    double kitti_frame_period_s = 0.1;
    double max_pose_gap_s = 0.5;
    std::vector<double> T_body_lidar;  ///< 12 or 16 row-major values; empty: identity (or extrinsic_file)
    std::string extrinsic_file;
    std::string extrinsic_key = "T_body_lidar";
    ExtrinsicSource extrinsic_source = ExtrinsicSource::Keys;
    std::string body_frame;
    std::string bag_tf_topic = "/tf_static";
    double min_range_m = 3.0;
    double max_range_m = 80.0;
    bool deskew = true;
    double voxel_size_m = 0.05;
    RingSource rings = RingSource::Field;
    ReflectivityNormalisation reflectivity_normalisation = ReflectivityNormalisation::RangeRing;
    double range_bin_m = 2.0;
    double intensity_scale = 0.0;
    bool carve = true;
    double carve_voxel_m = 0.2;
    double carve_clearance_m = 0.3;
    double carve_min_sin = 0.05;
    double carve_max_range_m = 50.0;
    int carve_min_pass_scans = 2;
    double carve_pass_ratio = 0.25;
    std::string output;
    std::string export_cloud;
    std::string export_removed;
    CloudEncoding export_encoding = CloudEncoding::Binary;
    /// optional: a folder where the map's distance field tiles are written whole, for a streamed field to read
    /// ([GeometricLocalization] field_tile_cache), with this voxel and truncation (those of the tracker)
    std::string field_tile_cache;
    double field_voxel_m = 0.04, field_max_distance_m = 0.5;

    void declare(core::OptionTable& t) override;
    /** The declared ranges, then the rules between keys: InputError naming the key. */
    void check(const std::string& config_name) const;
    /** The options of ScanPoses, scan_times = auto resolved. With trajectory_format = bag the caller fills `poses`
     *  from the bag (libs/ros readBagTrajectory: trajectoryBag(), bag_pose_topic); with extrinsic_source = tf_static
     *  it fills T_body_lidar (libs/ros readBagExtrinsic: bag, bag_tf_topic, body_frame, the scans' frame_id). */
    ScanPoseOptions poseOptions() const;
    /** trajectory_format = bag: the bag holding the poses (trajectory, or the scans' bag when trajectory is empty). */
    std::string trajectoryBag() const { return trajectory.empty() ? bag : trajectory; }
    /** What the scans are, for messages: the folder, or "<bag> topic <topic>". */
    std::string scansName() const;
    CarvingOptions carvingOptions() const;
    ScanFilter scanFilter() const;
};

struct MapBuildResult
{
    LidarMap map;      ///< the static map
    LidarMap removed;  ///< the fused points the carving removed
    size_t scans = 0, points_read = 0, points_used = 0, deskewed_scans = 0;
    size_t points_invalid = 0;  ///< points without a position (NaN in organised clouds), dropped on reading
    size_t fused_voxels = 0, fusion_bytes = 0;
    CarvingStats carving;
    IntensityNormalisation intensity;  ///< raw -> [0, 1] divisor
    ReflectivityConsistency consistency;
    std::string reflectivity_model;  ///< ReflectivityModel::summary()
    size_t reflectivity_clamped = 0;
    double seconds[3] = {0, 0, 0};      ///< wall time per pass
    double cpu_seconds[3] = {0, 0, 0};  ///< CPU time per pass (single-threaded: about the wall time)
};

/** Called after each scan of each pass: pass (1..3), scans done, scans in all. */
using MapBuildProgress = std::function<void(int pass, size_t done, size_t total)>;

MapBuildResult buildMap(const MapBuildOptions& options, const ScanSource& source, const ScanPoses& poses,
                        const MapBuildProgress& progress = {});

}  // namespace quasiloc::map
