// bench_distance_field: build time and memory of the map's distance field, dense grid against sparse bricks.
//
//     bench_distance_field <map file> [dense|sparse|auto] [voxel_m=0.04] [max_distance_m=0.5]
//
// Prints one row: the map, the layout, the grid, the build time, the field's own memory, the process's peak
// resident memory (VmHWM, after loading the map and building the field) and the distance queries' time. Run one
// process per layout: the peak is the process's.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <quasiloc/map/distance_field.h>
#include <random>
#include <string>

namespace
{
double peakResidentMb()
{
    std::ifstream status("/proc/self/status");
    for (std::string line; std::getline(status, line);)
        if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
    return -1;
}
}  // namespace

int main(int argc, char** argv)
{
    using namespace quasiloc;
    if (argc < 2)
    {
        std::cerr << "usage: bench_distance_field <map file> [dense|sparse|auto] [voxel_m] [max_distance_m]\n";
        return 2;
    }
    try
    {
        const std::string layout = argc > 2 ? argv[2] : "auto";
        map::DistanceFieldOptions o;
        o.layout = layout == "dense"    ? map::DistanceFieldLayout::Dense
                   : layout == "sparse" ? map::DistanceFieldLayout::Sparse
                                        : map::DistanceFieldLayout::Auto;
        if (argc > 3) o.voxel_m = std::stod(argv[3]);
        if (argc > 4) o.max_distance_m = std::stod(argv[4]);
        o.margin_m = std::max(1.0, o.max_distance_m);  // as the global localizer builds it
        const map::LidarMap map = map::LidarMap::load(argv[1]);
        const double loaded_mb = peakResidentMb();
        const auto t0 = std::chrono::steady_clock::now();
        const map::DistanceField f = map::DistanceField::build(map, o, argv[1]);
        const double build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        // Queries near the surface (map points moved by up to 0.3 m), as the stereo factor makes them.
        std::mt19937 rng(1);
        std::uniform_int_distribution<size_t> pick(0, map.size() - 1);
        std::uniform_real_distribution<float> jitter(-0.3f, 0.3f);
        std::vector<Eigen::Vector3f> queries;
        for (int q = 0; q < 1'000'000; ++q)
            queries.push_back(map.point(pick(rng)) + Eigen::Vector3f(jitter(rng), jitter(rng), jitter(rng)));
        const auto t1 = std::chrono::steady_clock::now();
        double sum = 0;
        Eigen::Vector3f g;
        for (const auto& p : queries) sum += f.distance(p, g);
        const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t1).count() /
                          double(queries.size());
        const Eigen::Vector3i n = f.dimensions();
        std::printf("| %s | %zu | %s | %d x %d x %d | %.2f s | %.0f MB | %.0f MB | %.0f MB | %.0f ns | %.3f |\n",
                    argv[1], map.size(), f.sparse() ? "sparse" : "dense", n.x(), n.y(), n.z(), build_s,
                    double(f.memoryBytes()) / 1048576.0, loaded_mb, peakResidentMb(), ns, sum / double(queries.size()));
        return 0;
    }
    catch (const std::exception& e)
    {
        std::cerr << "bench_distance_field: error: " << e.what() << "\n";
        return 1;
    }
}
