#include "map_build_app.h"

#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <quasiloc/core/error.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/map/distance_field.h>
#include <quasiloc/map/map_build.h>
#include <quasiloc/map/surface_thickness.h>
#include <quasiloc/ros/bag_scan_source.h>
#include <sstream>

namespace quasiloc::map_build
{
namespace
{
const char* const kUsageText = R"(map-build: builds a quasiloc LidarMap from LiDAR scans and their poses: voxel fusion
(mean position, mean reflectivity), reflectivity normalised per range and per ring, moving things removed by
free-space carving. See docs/map-build.md.

Usage:
  map-build <config.ini> [--set MapBuild.key=value]... [--print-timing]

Options, section [MapBuild]:
)";

const char* const kPassNames[] = {"", "fuse", "carve", "reflectivity"};

std::string megabytes(double bytes)
{
    std::ostringstream s;
    s << std::fixed << std::setprecision(1) << bytes / 1.0e6 << " MB";
    return s.str();
}

/** The scans: a folder's files, or a bag topic's PointCloud2 messages with their header stamps. */
struct Scans
{
    std::unique_ptr<map::ScanSource> source;
    std::vector<std::string> names;
    std::vector<double> stamps;  ///< bag scans: their stamps (scan_times = stamps)
    std::string description;
    std::string lidar_frame;  ///< bag scans: their header.frame_id (with extrinsic_source = tf_static)
    std::string topic;        ///< bag scans: their topic
};

Scans openScans(const map::MapBuildOptions& opt, const std::string& config_path)
{
    Scans s;
    if (opt.source == map::ScanSourceKind::Bag)
    {
        core::requireInputFiles(config_path, "MapBuild", {{"bag", opt.bag}});
        auto bag = std::make_unique<ros::BagScanSource>(opt.bag, opt.bag_lidar_topic);
        if (opt.scan_times == map::ScanTimeSource::Auto || opt.scan_times == map::ScanTimeSource::Stamps)
            s.stamps = bag->stampsSeconds();
        s.description = bag->describe();
        s.topic = bag->topic();
        if (opt.extrinsic_source == map::ExtrinsicSource::TfStatic) s.lidar_frame = bag->lidarFrame();
        s.source = std::move(bag);
    }
    else
    {
        auto folder = std::make_unique<map::FolderScanSource>(opt.scan_folder, opt.scan_format);
        s.description =
            std::to_string(folder->size()) + " " + map::toString(folder->format()) + " files in " + opt.scan_folder;
        s.source = std::move(folder);
    }
    for (size_t i = 0; i < s.source->size(); ++i) s.names.push_back(s.source->name(i));
    return s;
}

/** The 12 values of a 3x4 row-major matrix, each exact (17 significant digits): a T_body_lidar key's value. */
std::string rowMajor(const Eigen::Isometry3d& T)
{
    std::ostringstream s;
    s << std::setprecision(17);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) s << (r + c > 0 ? " " : "") << T.matrix()(r, c);
    return s.str();
}

/** One line per pass at 0, 10, 20 ... 100 % of its scans. */
void printProgress(int pass, size_t done, size_t total)
{
    static int last_decile[4] = {-1, -1, -1, -1};
    const int decile = int(10 * done / total);
    if (decile == last_decile[pass] && done != total) return;
    last_decile[pass] = decile;
    std::cout << "pass " << pass << " (" << kPassNames[pass] << ") " << done << "/" << total << " scans\n"
              << std::flush;
}
}  // namespace

std::string usage()
{
    std::string text = kUsageText;
    for (const core::OptionDescription& d : map::MapBuildOptions().describe())
    {
        std::string line = "  " + d.key + std::string(d.key.size() < 28 ? 28 - d.key.size() : 1, ' ') + d.doc;
        if (!d.unit.empty()) line += " [" + d.unit + "]";
        text += line + "\n" + std::string(30, ' ') + (d.range.empty() ? "" : d.range + "; ") + "default " +
                (d.default_value.empty() ? "(empty)" : d.default_value) + "\n";
    }
    return text;
}

int run(const core::CommandLine& cmd)
{
    const auto t0 = std::chrono::steady_clock::now();
    for (const auto& f : cmd.flags) throw core::InputError("command line", "unexpected argument '" + f + "'");
    const auto cfg = core::loadConfig(cmd);
    map::MapBuildOptions opt;
    core::loadOptionsChecked(opt, cfg, "MapBuild", cmd.config_path);
    opt.check(cmd.config_path);
    if (opt.trajectory_format != map::TrajectoryFormat::Bag)
        core::requireInputFiles(cmd.config_path, "MapBuild", {{"trajectory", opt.trajectory}});
    core::requireInputFiles(cmd.config_path, "MapBuild",
                            {{"scan_times_file", opt.scan_times_file}, {"extrinsic_file", opt.extrinsic_file}}, false);

    const Scans scans = openScans(opt, cmd.config_path);
    const map::ScanSource& source = *scans.source;
    map::ScanPoseOptions pose_options = opt.poseOptions();
    if (opt.trajectory_format == map::TrajectoryFormat::Bag)
        pose_options.poses = ros::readBagTrajectory(opt.trajectoryBag(), opt.bag_pose_topic);
    std::string extrinsic_chain;
    if (opt.extrinsic_source == map::ExtrinsicSource::TfStatic)
    {
        const ros::BagExtrinsic e =
            ros::readBagExtrinsic(opt.bag, opt.bag_tf_topic, opt.body_frame, scans.lidar_frame, scans.topic);
        pose_options.T_body_lidar = e.T_body_lidar;
        extrinsic_chain = e.chain;
    }
    const map::ScanPoses poses(pose_options, scans.names, scans.stamps);
    std::cout << "scans       " << scans.description << ", poses from " << pose_options.trajectory;
    if (opt.trajectory_format == map::TrajectoryFormat::Bag)
        std::cout << " (" << pose_options.poses.poses.size() << " poses)";
    std::cout << "\n";
    if (opt.extrinsic_source == map::ExtrinsicSource::TfStatic)
        std::cout << "extrinsic   from " << opt.bag << " topic " << opt.bag_tf_topic << ": " << extrinsic_chain
                  << "\n            T_body_lidar = " << rowMajor(pose_options.T_body_lidar) << "\n";

    const map::MapBuildResult r = map::buildMap(opt, source, poses, printProgress);

    // Every output is staged: they all appear together, or none does.
    core::StagedOutputs staged;
    const std::string ini_path = opt.output + ".ini";
    const std::string map_tmp = staged.addFile(opt.output);
    const std::string ini_tmp = staged.addFile(ini_path);
    r.map.save(map_tmp);
    if (!opt.export_cloud.empty())
        map::exportCloud(r.map, staged.addFile(opt.export_cloud), map::detectCloudFormat(opt.export_cloud),
                         opt.export_encoding);
    if (!opt.export_removed.empty())
    {
        core::require(!r.removed.empty(), opt.export_removed, "no point was removed: nothing to export");
        map::exportCloud(r.removed, staged.addFile(opt.export_removed), map::detectCloudFormat(opt.export_removed),
                         opt.export_encoding);
    }
    core::writeEffectiveConfig(ini_tmp, {{"MapBuild", &opt}}, "map-build effective configuration");
    staged.commit();
    if (!opt.field_tile_cache.empty())
    {  // the field as the tracker builds it (GeometricLocalizer::buildField), every tile of it on disk
        const auto tf = std::chrono::steady_clock::now();
        map::DistanceFieldOptions fo;
        fo.layout = map::DistanceFieldLayout::Streamed;
        fo.voxel_m = opt.field_voxel_m;
        fo.max_distance_m = opt.field_max_distance_m;
        fo.margin_m = std::max(1.0, opt.field_max_distance_m);
        fo.tile_cache = opt.field_tile_cache;
        const size_t tiles = map::DistanceField::build(r.map, fo, opt.output).writeAllTiles();
        std::cout << "field tiles " << tiles << " written to " << opt.field_tile_cache << " in "
                  << std::chrono::duration<double>(std::chrono::steady_clock::now() - tf).count() << " s\n";
    }

    const double total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cout << std::fixed << std::setprecision(3);
    std::cout << "points      " << r.points_read << " read";
    if (r.points_invalid > 0) std::cout << " (" << r.points_invalid << " without a position dropped)";
    std::cout << ", " << r.points_used << " within " << opt.min_range_m << ".." << opt.max_range_m << " m; "
              << r.deskewed_scans << " of " << r.scans << " scans deskewed (per-point times)\n"
              << "fusion      " << r.fused_voxels << " voxels of " << opt.voxel_size_m << " m ("
              << megabytes(double(r.fusion_bytes)) << ")\n";
    if (opt.carve)
        std::cout << "carving     " << r.carving.free_voxels << " of " << r.carving.voxels << " voxels of "
                  << opt.carve_voxel_m << " m free (" << megabytes(double(r.carving.memory_bytes)) << "), "
                  << r.carving.rays << " rays, " << r.carving.steps << " voxel steps; " << r.removed.size()
                  << " points removed\n";
    std::cout << "reflectivity " << r.intensity.rule << "; " << r.reflectivity_clamped << " values clamped\n"
              << r.reflectivity_model << "\n";
    if (r.consistency.voxels > 0)
        std::cout << "consistency  within-voxel coefficient of variation " << r.consistency.raw_cv << " raw -> "
                  << r.consistency.normalised_cv << " normalised (" << r.consistency.voxels << " voxels)\n";
    std::cout << "wrote       " << r.map.size() << " points to " << opt.output << ", effective config " << ini_path
              << "\n"
              << "surfaces    thickness " << map::describe(map::measureSurfaceThickness(r.map)) << "\n";
    std::cout << "time        wall (CPU) pass 1 " << r.seconds[0] << " (" << r.cpu_seconds[0] << ") s, pass 2 "
              << r.seconds[1] << " (" << r.cpu_seconds[1] << ") s, pass 3 " << r.seconds[2] << " (" << r.cpu_seconds[2]
              << ") s, total wall " << total_s << " s\n";
    return 0;
}

}  // namespace quasiloc::map_build
