// bench_map: VisibilityIndex query time (the renderer's culling step).
//  - a synthetic 3 M-point room (EuRoC V1-sized box with clutter, 1 m blocks) seen by the EuRoC cam0
//    model (752x480, radtan) from 16 poses looking in every direction. Bound: <= 500 us per query.
//  - the real KITTI map (1.06 M points, 165 x 133 m, 1 m blocks) seen by the rectified cam2 (1242x375)
//    from the 78 poses of the drive, max range 80 m. Bound: <= 500 us per query.
// Also times index construction and the view-cone computation. Every bound is printed with its measure.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/map/map_import.h>
#include <quasiloc/map/visibility_index.h>
#include <random>
#include <sstream>

using namespace quasiloc;

namespace
{
constexpr double kQueryBoundUs = 500.0;
const std::string kData = std::string(QUASILOC_SHARED_DIR) + "/data";

struct Measure
{
    double us_per_query = 0, returned_fraction = 0, ranges = 0;
};
std::map<std::string, Measure> g_measures;

/** Walls, floor, ceiling of the EuRoC V1 room extent plus 12 boxes (furniture), 3 M points. */
map::LidarMap syntheticRoom(size_t n)
{
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> U(0.f, 1.f);
    const Eigen::Vector3f lo(-4.4f, -3.5f, 0.f), hi(3.7f, 5.0f, 3.4f);
    std::vector<std::pair<Eigen::Vector3f, Eigen::Vector3f>> boxes = {{lo, hi}};
    for (int b = 0; b < 12; ++b)
    {
        const Eigen::Vector3f c(lo.x() + 1 + U(rng) * 6, lo.y() + 1 + U(rng) * 6.5f, 0.f);
        const Eigen::Vector3f half(0.2f + U(rng) * 0.5f, 0.2f + U(rng) * 0.5f, 0.3f + U(rng) * 0.8f);
        boxes.push_back(
            {c - Eigen::Vector3f(half.x(), half.y(), 0), c + Eigen::Vector3f(half.x(), half.y(), 2 * half.z())});
    }
    map::LidarMap m;
    m.reserve(n);
    for (size_t i = 0; i < n; ++i)
    {
        const auto& [blo, bhi] = boxes[i % 3 == 0 ? 1 + (i / 3) % 12 : 0];  // a third of the points on boxes
        Eigen::Vector3f p = blo + (bhi - blo).cwiseProduct(Eigen::Vector3f(U(rng), U(rng), U(rng)));
        const int face = static_cast<int>(U(rng) * 6) % 6;
        p[face / 2] = (face % 2) ? bhi[face / 2] : blo[face / 2];
        m.addPoint(p.x(), p.y(), p.z(), U(rng));
    }
    return m;
}

std::vector<mrpt::poses::CPose3D> roomPoses()
{
    std::vector<mrpt::poses::CPose3D> poses;
    const mrpt::poses::CPose3D T_body_cam(0, 0, 0, -M_PI / 2, 0, -M_PI / 2);  // z forward, y down
    for (int h = 0; h < 2; ++h)
        for (int k = 0; k < 8; ++k)
            poses.push_back(
                mrpt::poses::CPose3D(-0.5 + 0.3 * h, 0.4 - 0.2 * h, 1.2 + 0.5 * h, k * M_PI / 4, 0.15 + 0.1 * h, 0.0) +
                T_body_cam);
    return poses;
}

std::vector<mrpt::poses::CPose3D> kittiPoses()
{
    std::ifstream in(kData + "/kitti_raw_seq78/poses_cam2.txt");
    std::vector<mrpt::poses::CPose3D> poses;
    std::string line;
    while (std::getline(in, line))
    {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream s(line);
        std::vector<double> v(12);
        for (auto& x : v) s >> x;
        poses.push_back(core::fromMatrixRowMajor(v, "poses_cam2.txt"));
    }
    return poses;
}

void runQueries(benchmark::State& state, const map::VisibilityIndex& index, const core::CameraModel& cam,
                const std::vector<mrpt::poses::CPose3D>& poses, double max_range, const std::string& name)
{
    const auto cone = map::VisibilityIndex::viewCone(cam);
    std::vector<map::VisibilityIndex::Range> ranges;
    size_t k = 0, queries = 0, returned = 0, n_ranges = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (auto _ : state)
    {
        index.query(poses[k], cone, max_range, ranges);
        benchmark::DoNotOptimize(ranges.data());
        returned += map::VisibilityIndex::countPoints(ranges);
        n_ranges += ranges.size();
        k = (k + 1) % poses.size();
        ++queries;
    }
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    Measure& m = g_measures[name];
    m.us_per_query = 1e6 * s / std::max<size_t>(queries, 1);
    m.returned_fraction = double(returned) / std::max<size_t>(queries, 1) / index.size();
    m.ranges = double(n_ranges) / std::max<size_t>(queries, 1);
    state.counters["returned_fraction"] = m.returned_fraction;
    state.counters["ranges"] = m.ranges;
    state.counters["bound_us"] = kQueryBoundUs;
}

const map::LidarMap& roomMap()
{
    static const map::LidarMap m = syntheticRoom(3000000);
    return m;
}
const map::LidarMap& kittiMap()
{
    static const map::LidarMap m =
        map::importCloud(kData + "/kitti_raw_seq78/map_even_frames_5cm.ply", map::ImportOptions{}).map;
    return m;
}

void BM_QueryRoom3M(benchmark::State& state)
{
    static const map::VisibilityIndex index(roomMap(), {});
    static const auto cam = core::CameraModel::fromEurocYaml(kData + "/euroc/calib/cam0_sensor.yaml");
    runQueries(state, index, cam, roomPoses(), 10.0, "room 3M, EuRoC cam0, 1 m blocks, range 10 m");
}

void BM_QueryKitti(benchmark::State& state)
{
    static const map::VisibilityIndex index(kittiMap(), {});
    const auto cam = core::CameraModel::pinhole(1242, 375, 721.5377, 721.5377, 609.5593, 172.854);
    static const auto poses = kittiPoses();
    runQueries(state, index, cam, poses, 80.0, "KITTI 1.06M, cam2, 1 m blocks, range 80 m");
}

void BM_QueryKittiNoSuperblocks(benchmark::State& state)
{
    map::VisibilityIndex::Options o;
    o.superblock_blocks = 1;
    static const map::VisibilityIndex index(kittiMap(), o);
    const auto cam = core::CameraModel::pinhole(1242, 375, 721.5377, 721.5377, 609.5593, 172.854);
    static const auto poses = kittiPoses();
    runQueries(state, index, cam, poses, 80.0, "KITTI 1.06M, flat block list (superblock_blocks=1)");
}

void BM_BuildIndexRoom3M(benchmark::State& state)
{
    const map::LidarMap& m = roomMap();
    for (auto _ : state)
    {
        map::VisibilityIndex index(m, {});
        benchmark::DoNotOptimize(index.numBlocks());
        state.counters["blocks"] = double(index.numBlocks());
    }
}

void BM_ViewConeRadtan(benchmark::State& state)
{
    const auto cam = core::CameraModel::fromEurocYaml(kData + "/euroc/calib/cam0_sensor.yaml");
    for (auto _ : state) benchmark::DoNotOptimize(map::VisibilityIndex::viewCone(cam).side_normals.size());
}
}  // namespace

BENCHMARK(BM_QueryRoom3M)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_QueryKitti)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_QueryKittiNoSuperblocks)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BuildIndexRoom3M)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_ViewConeRadtan)->Unit(benchmark::kMicrosecond);

int main(int argc, char** argv)
{
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    std::printf("\nVisibilityIndex query bounds (measured vs bound):\n");
    for (const auto& [name, m] : g_measures)
        std::printf("  %-55s %8.1f us/query (bound %.0f us) %s | %.1f%% of the points returned in %.1f ranges\n",
                    name.c_str(), m.us_per_query, kQueryBoundUs, m.us_per_query <= kQueryBoundUs ? "OK" : "OVER",
                    100 * m.returned_fraction, m.ranges);
    return 0;
}
