// bench_carving: free-space carving of a map-build run two ways, to choose one (docs/map-build.md):
//   own     the product's: 3D DDA through a hash of occupied voxels, pass counts per scan (free_space_carving.h);
//   octomap OctoMap's occupancy octree (liboctomap-dev): every scan inserted with insertPointCloud (rays from the
//           scan's origin, log-odds hit / miss updates, clamping), then a fused point is removed when its leaf ends
//           free (occupancy below 0.5).
// Both start from the same fused voxels ([MapBuild] of the INI, carve settings shared: voxel size, max range).
// Prints time (wall and CPU), the carving structure's memory and the process's peak RSS, points removed; writes
// <output_dir>/<method>_map.ply and <method>_removed.ply for scripts/kitti_map_build_check.py (static kept,
// vehicles removed).
//   bench_carving <config.ini> [--set MapBuild.key=value] [--set BenchCarving.method=own|octomap] ...
// Run one method per process so the peak RSS is its own.
#include <octomap/OcTree.h>

#include <chrono>
#include <ctime>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/map/map_build.h>

namespace
{
using namespace quasiloc;

struct BenchCarvingOptions : public core::DeclaredOptions
{
    std::string method = "own";
    std::string output_dir = "/tmp/quasiloc_bench_carving";
    double prob_hit = 0.7, prob_miss = 0.4, clamp_min = 0.12, clamp_max = 0.97;
    void declare(core::OptionTable& t) override
    {
        t.add("method", method, "own | octomap");
        t.add("output_dir", output_dir, "where <method>_map.ply and <method>_removed.ply go");
        t.add("prob_hit", prob_hit, "", core::Range::strictlyBetween(0.5, 1), "OctoMap: hit probability");
        t.add("prob_miss", prob_miss, "", core::Range::strictlyBetween(0, 0.5), "OctoMap: miss probability");
        t.add("clamp_min", clamp_min, "", core::Range::strictlyBetween(0, 0.5), "OctoMap: clamping (min)");
        t.add("clamp_max", clamp_max, "", core::Range::strictlyBetween(0.5, 1), "OctoMap: clamping (max)");
    }
};

size_t peakRssBytes()
{
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("VmHWM:", 0) == 0) return std::stoul(line.substr(6)) * 1024;
    return 0;
}

struct Clock
{
    std::chrono::steady_clock::time_point wall = std::chrono::steady_clock::now();
    std::clock_t cpu = std::clock();
    double wallS() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count(); }
    double cpuS() const { return double(std::clock() - cpu) / CLOCKS_PER_SEC; }
};

/** OctoMap: the scans inserted, then the fused points split by their leaf's occupancy. */
void carveWithOctomap(const map::MapBuildOptions& o, const BenchCarvingOptions& b, const map::ScanSource& source,
                      const map::ScanPoses& poses, const map::LidarMap& fused, map::LidarMap& kept,
                      map::LidarMap& removed, size_t& memory)
{
    octomap::OcTree tree(o.carve_voxel_m);
    tree.setProbHit(b.prob_hit);
    tree.setProbMiss(b.prob_miss);
    tree.setClampingThresMin(b.clamp_min);
    tree.setClampingThresMax(b.clamp_max);
    const map::ScanFilter filter = o.scanFilter();
    for (size_t i = 0; i < source.size(); ++i)
    {
        const map::WorldScan w = map::toWorld(source.read(i), poses, i, filter);
        octomap::Pointcloud cloud;
        cloud.reserve(w.size());
        for (const Eigen::Vector3f& p : w.points) cloud.push_back(p.x(), p.y(), p.z());
        const Eigen::Vector3f& origin = w.origins.front();  // one origin per scan: OctoMap's model
        tree.insertPointCloud(cloud, octomap::point3d(origin.x(), origin.y(), origin.z()), o.carve_max_range_m,
                              /*lazy_eval=*/false, /*discretize=*/true);
        std::cout << "octomap scan " << i + 1 << "/" << source.size() << "\r" << std::flush;
    }
    std::cout << "\n";
    memory = tree.memoryUsage();
    for (size_t k = 0; k < fused.size(); ++k)
    {
        const Eigen::Vector3f p = fused.point(k);
        const octomap::OcTreeNode* node = tree.search(double(p.x()), double(p.y()), double(p.z()));
        const bool free = node != nullptr && !tree.isNodeOccupied(node);
        (free ? removed : kept).addPoint(p.x(), p.y(), p.z(), fused.reflectivity(k));
    }
}

int run(const core::CommandLine& cmd)
{
    const auto cfg = core::loadConfig(cmd);
    map::MapBuildOptions o;
    core::loadOptionsChecked(o, cfg, "MapBuild", cmd.config_path);
    o.check(cmd.config_path);
    BenchCarvingOptions b;
    core::loadOptionsChecked(b, cfg, "BenchCarving", cmd.config_path);
    core::require(b.method == "own" || b.method == "octomap", "[BenchCarving] method", "own or octomap");

    const map::FolderScanSource source(o.scan_folder, o.scan_format);
    std::vector<std::string> names;
    for (size_t i = 0; i < source.size(); ++i) names.push_back(source.name(i));
    const map::ScanPoses poses(o.poseOptions(), names);

    map::LidarMap kept, removed;
    size_t memory = 0;
    double carve_wall = 0, carve_cpu = 0, fuse_wall = 0;
    if (b.method == "own")
    {
        map::MapBuildResult r = map::buildMap(o, source, poses);
        carve_wall = r.seconds[1];  // pass 2 is the ray casting (with the reflectivity observations)
        carve_cpu = r.cpu_seconds[1];
        fuse_wall = r.seconds[0] + r.seconds[2];
        memory = r.carving.memory_bytes;
        kept = std::move(r.map);
        removed = std::move(r.removed);
    }
    else
    {
        map::MapBuildOptions uncarved = o;
        uncarved.carve = false;
        map::MapBuildResult r = map::buildMap(uncarved, source, poses);
        fuse_wall = r.seconds[0] + r.seconds[1] + r.seconds[2];
        const Clock clock;
        carveWithOctomap(o, b, source, poses, r.map, kept, removed, memory);
        carve_wall = clock.wallS();
        carve_cpu = clock.cpuS();
    }
    map::exportCloud(kept, b.output_dir + "/" + b.method + "_map.ply");
    if (!removed.empty()) map::exportCloud(removed, b.output_dir + "/" + b.method + "_removed.ply");
    std::cout << std::fixed << std::setprecision(2) << "| method | carving wall [s] | carving CPU [s] | fusion [s] | "
              << "carving structure [MB] | peak RSS [MB] | points kept | points removed "
                 "|\n|---|---|---|---|---|---|---|---|\n"
              << "| " << b.method << " | " << carve_wall << " | " << carve_cpu << " | " << fuse_wall << " | "
              << memory / 1.0e6 << " | " << peakRssBytes() / 1.0e6 << " | " << kept.size() << " | " << removed.size()
              << " |\n";
    return 0;
}
}  // namespace

int main(int argc, char** argv)
{
    return core::runProgram(argc, argv, "Usage: bench_carving <config.ini> [--set Section.key=value]...", run);
}
