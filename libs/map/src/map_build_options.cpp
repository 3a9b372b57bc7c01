// The keys of [MapBuild], each declared once (name, member, unit, range, meaning), and the rules between keys.
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/map/map_build.h>

namespace quasiloc::map
{
using core::Range;

void MapBuildOptions::declare(core::OptionTable& t)
{
    t.addEnum("source", source, {{"folder", ScanSourceKind::Folder}, {"bag", ScanSourceKind::Bag}},
              "where the scans come from: folder = one file per scan (scan_folder); bag = one sensor_msgs/PointCloud2 "
              "message per scan (bag, bag_lidar_topic)");
    t.add("scan_folder", scan_folder, "the folder of scans (KITTI .bin, .pcd or .ply), read in file-name order");
    t.addEnum("scan_format", scan_format,
              {{"auto", CloudFormat::Auto},
               {"kitti", CloudFormat::KittiBin},
               {"pcd", CloudFormat::Pcd},
               {"ply", CloudFormat::Ply}},
              "the scans' format; auto = from the extensions (one format per folder)");
    t.add("bag", bag,
          "source = bag: a ROS 1 .bag file, a rosbag2 folder (sqlite3 or mcap storage), or one .db3 / .mcap file");
    t.add("bag_lidar_topic", bag_lidar_topic,
          "source = bag: the sensor_msgs/PointCloud2 topic of the scans; empty: the bag's only PointCloud2 topic");
    t.add("trajectory", trajectory,
          "the LiDAR-carrying body's poses T_world_body: a TUM file, KITTI poses, or a bag (trajectory_format = bag; "
          "empty: the scans' bag)");
    t.addEnum("trajectory_format", trajectory_format,
              {{"tum", TrajectoryFormat::Tum}, {"kitti", TrajectoryFormat::Kitti}, {"bag", TrajectoryFormat::Bag}},
              "tum: t x y z qx qy qz qw per line; kitti: a 3x4 row-major matrix per line, line k = frame k; bag: the "
              "poses of bag_pose_topic (header stamps), interpolated as TUM poses are");
    t.add("bag_pose_topic", bag_pose_topic,
          "trajectory_format = bag: a geometry_msgs/PoseStamped, nav_msgs/Odometry or geometry_msgs/TransformStamped "
          "topic of T_world_body (LiDAR-inertial odometry's output)");
    t.addEnum("scan_times", scan_times,
              {{"auto", ScanTimeSource::Auto},
               {"names", ScanTimeSource::FileNames},
               {"file", ScanTimeSource::TimesFile},
               {"order", ScanTimeSource::Order},
               {"stamps", ScanTimeSource::Stamps}},
              "a scan's time (TUM, bag poses) or frame (KITTI): the number its file name spells, scan_times_file's "
              "line, its index in scan order, or its PointCloud2 header stamp; auto = names for files, stamps for a "
              "bag");
    t.add("scan_times_file", scan_times_file, "scan_times = file: one time per line, in the scans' file-name order");
    t.add("scan_time_scale", scan_time_scale, "s", Range::above(0),
          "TUM: seconds per unit of the names' or times file's numbers (1e-9 for nanoseconds)");
    t.add("kitti_frame_period_s", kitti_frame_period_s, "s", Range::above(0),
          "KITTI poses: time between two pose lines (for per-point deskewing)");
    t.add("max_pose_gap_s", max_pose_gap_s, "s", Range::above(0),
          "TUM: a time between two poses further apart than this has no pose (an error naming the scan)");
    t.add("T_body_lidar", T_body_lidar, "m", Range::any(),
          "the LiDAR's pose on the body, 12 (3x4) or 16 (4x4) row-major values; empty: identity, extrinsic_file, or "
          "extrinsic_source = tf_static");
    t.add("extrinsic_file", extrinsic_file,
          "instead of T_body_lidar: a KITTI-style calibration file holding the line '<extrinsic_key>: 12 values'");
    t.add("extrinsic_key", extrinsic_key, "the line of extrinsic_file (e.g. T_cam2rect_velo for kitti_raw_seq78)");
    t.addEnum(
        "extrinsic_source", extrinsic_source,
        {{"keys", ExtrinsicSource::Keys}, {"tf_static", ExtrinsicSource::TfStatic}},
        "where T_body_lidar comes from: keys = T_body_lidar or extrinsic_file; tf_static = the scans' bag's static "
        "transforms (bag_tf_topic), chained from body_frame to the scans' PointCloud2 header.frame_id (source = "
        "bag)");
    t.add("body_frame", body_frame,
          "extrinsic_source = tf_static: the frame the trajectory's poses are of (FAST-LIO: body or the IMU's frame; "
          "LIO-SAM: base_link)");
    t.add("bag_tf_topic", bag_tf_topic,
          "extrinsic_source = tf_static: the tf2_msgs/TFMessage topic of the static transforms in bag");
    t.add("min_range_m", min_range_m, "m", Range::atLeast(0), "points nearer the LiDAR are dropped (the vehicle)");
    t.add("max_range_m", max_range_m, "m", Range::above(0), "points farther away are dropped");
    t.add("deskew", deskew, "move each point with the pose at its own time, where the scans carry per-point times");
    t.add("voxel_size_m", voxel_size_m, "m", Range::above(0),
          "the map's voxels: one point per occupied voxel (mean position and reflectivity)");
    t.addEnum("rings", rings,
              {{"field", RingSource::Field}, {"azimuth_wrap", RingSource::AzimuthWrap}, {"none", RingSource::None}},
              "ring numbers for the per-ring gain: the scans' ring field, estimated from azimuth wraps (scans stored "
              "laser by laser, as KITTI .bin), or none");
    t.addEnum("reflectivity_normalisation", reflectivity_normalisation,
              {{"range_ring", ReflectivityNormalisation::RangeRing},
               {"range", ReflectivityNormalisation::Range},
               {"ring", ReflectivityNormalisation::Ring},
               {"none", ReflectivityNormalisation::None}},
              "gains fitted from the scans themselves (scan_fusion.h): per range bin and/or per ring; none = raw");
    t.add("range_bin_m", range_bin_m, "m", Range::above(0), "width of the range bins of the range gain");
    t.add("intensity_scale", intensity_scale, "", Range::atLeast(0),
          "> 0: reflectivity = corrected raw / intensity_scale; 0 = map-import's automatic rule");
    t.add("carve", carve, "remove the points of moving things by free-space carving (free_space_carving.h)");
    t.add("carve_voxel_m", carve_voxel_m, "m", Range::above(0), "the carving grid's voxel size (>= voxel_size_m)");
    t.add("carve_clearance_m", carve_clearance_m, "m", Range::atLeast(0),
          "a ray stops this far above the surface it hits (along the surface normal)");
    t.add("carve_min_sin", carve_min_sin, "", Range::between(0.001, 1),
          "the sine of the incidence angle is taken as at least this (a ray stops at most clearance / this short)");
    t.add("carve_max_range_m", carve_max_range_m, "m", Range::above(0), "rays are walked this far at most");
    t.add("carve_min_pass_scans", carve_min_pass_scans, "", Range::atLeast(1),
          "a voxel is free when at least this many scans' rays passed through it ...");
    t.add("carve_pass_ratio", carve_pass_ratio, "", Range::atLeast(0),
          "... and those scans are at least this fraction of the scans that hit it");
    t.add("output", output, "the LidarMap file (the static map)");
    t.add("export_cloud", export_cloud, "optional: the map also as a cloud (.ply .pcd .bin .txt), to inspect");
    t.add("export_removed", export_removed, "optional: the carved-away points as a cloud, to inspect");
    t.addEnum("export_encoding", export_encoding,
              {{"binary", CloudEncoding::Binary},
               {"ascii", CloudEncoding::Ascii},
               {"binary_big_endian", CloudEncoding::BinaryBigEndian},
               {"binary_compressed", CloudEncoding::BinaryCompressed}},
              "encoding of the exports (PLY: no binary_compressed; PCD: no binary_big_endian)");
    t.add("field_tile_cache", field_tile_cache,
          "optional: a folder for the map's distance field tiles, written whole ([GeometricLocalization] "
          "field_layout = streamed, field_tile_cache: loading reads them instead of building)");
    t.add("field_voxel_m", field_voxel_m, "m", Range::above(0),
          "field_tile_cache: the field's voxel ([GeometricLocalization] field_voxel_m)");
    t.add("field_max_distance_m", field_max_distance_m, "m", Range::above(0),
          "field_tile_cache: the field's truncation ([GeometricLocalization] field_max_distance_m)");
}

void MapBuildOptions::check(const std::string& config_name) const
{
    const std::string at = config_name + " [MapBuild] ";
    checkRanges(config_name + " [MapBuild]");
    const bool from_bag = source == ScanSourceKind::Bag;
    if (from_bag)
    {
        core::require(!bag.empty(), at + "bag", "is required with source = bag");
        core::require(scan_times != ScanTimeSource::FileNames, at + "scan_times",
                      "names: bag scans have no file names (stamps, the default for a bag, uses their header stamps)");
    }
    else
    {
        core::require(!scan_folder.empty(), at + "scan_folder",
                      bag.empty() ? "is required" : "is required (bag is set: for scans from a bag set source = bag)");
        core::require(scan_times != ScanTimeSource::Stamps, at + "scan_times",
                      "stamps: only bag scans carry stamps (source = bag)");
    }
    if (trajectory_format == TrajectoryFormat::Bag)
    {
        core::require(!bag_pose_topic.empty(), at + "bag_pose_topic", "is required with trajectory_format = bag");
        core::require(!trajectoryBag().empty(), at + "trajectory",
                      "is required with trajectory_format = bag (the bag of the poses) when the scans are files");
    }
    else
        core::require(!trajectory.empty(), at + "trajectory", "is required");
    core::require(!output.empty(), at + "output", "is required");
    core::require(scan_times != ScanTimeSource::TimesFile || !scan_times_file.empty(), at + "scan_times_file",
                  "is required with scan_times = file");
    core::require(T_body_lidar.empty() || T_body_lidar.size() == 12 || T_body_lidar.size() == 16, at + "T_body_lidar",
                  "needs 12 or 16 values, not " + std::to_string(T_body_lidar.size()));
    core::require(T_body_lidar.empty() || extrinsic_file.empty(), at + "extrinsic_file",
                  "give the extrinsic once: T_body_lidar or extrinsic_file");
    if (extrinsic_source == ExtrinsicSource::TfStatic)
    {
        core::require(from_bag, at + "extrinsic_source",
                      "tf_static needs the scans from a bag (source = bag): their frame_id names the LiDAR's frame");
        core::require(!body_frame.empty(), at + "body_frame",
                      "is required with extrinsic_source = tf_static (the frame of the trajectory's poses)");
        core::require(!bag_tf_topic.empty(), at + "bag_tf_topic", "is required with extrinsic_source = tf_static");
        core::require(T_body_lidar.empty() && extrinsic_file.empty(), at + "extrinsic_source",
                      "tf_static: give the extrinsic once (T_body_lidar and extrinsic_file must be empty)");
    }
    core::require(min_range_m < max_range_m, at + "min_range_m", "must be below max_range_m");
    core::require(carve_voxel_m >= voxel_size_m, at + "carve_voxel_m", "must be >= voxel_size_m");
    for (const std::string* e : {&export_cloud, &export_removed})
        if (!e->empty()) requireEncodingSupported(detectCloudFormat(*e), export_encoding, at + "export_encoding");
}

ScanPoseOptions MapBuildOptions::poseOptions() const
{
    ScanPoseOptions p;
    p.trajectory =
        trajectory_format == TrajectoryFormat::Bag ? trajectoryBag() + " topic " + bag_pose_topic : trajectory;
    p.format = trajectory_format;
    p.times = scan_times;
    if (p.times == ScanTimeSource::Auto)
        p.times = source == ScanSourceKind::Bag ? ScanTimeSource::Stamps : ScanTimeSource::FileNames;
    p.times_file = scan_times_file;
    p.time_scale = scan_time_scale;
    p.frame_period_s = kitti_frame_period_s;
    p.max_pose_gap_s = max_pose_gap_s;
    if (extrinsic_source == ExtrinsicSource::TfStatic) return p;  // T_body_lidar from the bag, by the caller
    if (!T_body_lidar.empty())
        p.T_body_lidar = core::toIsometry(core::fromMatrixRowMajor(T_body_lidar, "[MapBuild] T_body_lidar"));
    else if (!extrinsic_file.empty())
        p.T_body_lidar = readCalibrationMatrix(extrinsic_file, extrinsic_key);
    return p;
}

std::string MapBuildOptions::scansName() const
{
    return source == ScanSourceKind::Bag ? bag + (bag_lidar_topic.empty() ? "" : " topic " + bag_lidar_topic)
                                         : scan_folder;
}

CarvingOptions MapBuildOptions::carvingOptions() const
{
    CarvingOptions c;
    c.voxel_m = carve_voxel_m;
    c.clearance_m = carve_clearance_m;
    c.min_sin = carve_min_sin;
    c.max_range_m = carve_max_range_m;
    c.min_pass_scans = carve_min_pass_scans;
    c.pass_ratio = carve_pass_ratio;
    return c;
}

ScanFilter MapBuildOptions::scanFilter() const
{
    ScanFilter f;
    f.min_range_m = min_range_m;
    f.max_range_m = max_range_m;
    f.deskew = deskew;
    f.rings = rings;
    return f;
}

}  // namespace quasiloc::map
