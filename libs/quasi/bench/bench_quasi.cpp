// bench_quasi: time of one quasi-image (culling + projection + completion + encoding) at 752x480 with the
// EuRoC cam0 model (radtan, distorted geometry) on a 3 M-point synthetic room, at poses looking in every
// direction. Bound: <= 8 ms per quasi-image (Release, 2 cores). Prints the per-stage split.
//
// Optional: QUASILOC_BENCH_MAP=<LidarMap file> and QUASILOC_BENCH_TUM=<TUM of T_world_cam0> add a benchmark
// on that map at (up to 50) poses of the trajectory, e.g. the simulator's output.
// QUASILOC_BENCH_CV_THREADS=<n>: cv::setNumThreads(n) first (0: no threads, for per-stage CPU costs).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <opencv2/core/utility.hpp>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <quasiloc/quasi/synthetic_scene.h>
#include <string>
#include <vector>

using namespace quasiloc;

namespace
{
constexpr double kBoundMs = 8.0;

core::CameraModel eurocCam0()
{
    return core::CameraModel::fromEurocYaml(std::string(QUASILOC_SHARED_DIR) + "/data/euroc/calib/cam0_sensor.yaml");
}

/** Camera poses inside the room: 8 headings x 2 heights, looking slightly down, camera z forward. */
std::vector<mrpt::poses::CPose3D> roomPoses()
{
    std::vector<mrpt::poses::CPose3D> poses;
    // Camera frame (z forward, x right, y down) -> world (x forward, y left, z up) at yaw 0.
    const mrpt::poses::CPose3D T_body_cam(0, 0, 0, -M_PI / 2, 0, -M_PI / 2);
    for (int h = 0; h < 2; ++h)
        for (int k = 0; k < 8; ++k)
        {
            const double yaw = k * M_PI / 4;
            const mrpt::poses::CPose3D T_world_body(-0.5 + 0.3 * h, 0.4 - 0.2 * h, 1.2 + 0.5 * h, yaw, 0.15 + 0.1 * h,
                                                    0.0);
            poses.push_back(T_world_body + T_body_cam);
        }
    return poses;
}

struct Split
{
    double culling = 0, projection = 0, completion = 0, encoding = 0, total = 0;
    double cpu_culling = 0, cpu_projection = 0, cpu_completion = 0, cpu_encoding = 0, cpu_total = 0;
    double candidates = 0, projected = 0, sparse = 0, completed = 0, occluded = 0;
    int n = 0;
};
std::map<std::string, Split> g_splits;

void runRenderBenchmark(benchmark::State& state, const map::LidarMap& map,
                        const std::vector<mrpt::poses::CPose3D>& poses, const std::string& name)
{
    const core::CameraModel cam = eurocCam0();
    quasi::QuasiOptions options;
    quasi::QuasiRenderer renderer(map, options);
    quasi::QuasiImage q;
    renderer.render(poses[0], cam, q);  // warm-up: image-sized buffers
    Split s;
    size_t i = 0;
    for (auto _ : state)
    {
        renderer.render(poses[i++ % poses.size()], cam, q);
        const auto& st = q.stats;
        s.culling += st.ms_culling, s.projection += st.ms_projection, s.completion += st.ms_completion;
        s.encoding += st.ms_encoding, s.total += st.msTotal();
        s.cpu_culling += st.cpu_ms_culling, s.cpu_projection += st.cpu_ms_projection;
        s.cpu_completion += st.cpu_ms_completion, s.cpu_encoding += st.cpu_ms_encoding;
        s.cpu_total += st.cpuMsTotal();
        s.candidates += double(st.candidate_points), s.projected += double(st.projected_points);
        s.sparse += double(st.sparse_pixels), s.completed += double(st.completed_pixels);
        s.occluded += double(st.occluded_pixels);
        ++s.n;
        benchmark::DoNotOptimize(q.bgr.data);
    }
    const double n = std::max(1, s.n);
    state.counters["cull_ms"] = s.culling / n;
    state.counters["proj_ms"] = s.projection / n;
    state.counters["compl_ms"] = s.completion / n;
    state.counters["enc_ms"] = s.encoding / n;
    state.counters["total_ms"] = s.total / n;
    state.counters["bound_ms"] = kBoundMs;
    state.counters["cpu_ms"] = s.cpu_total / n;
    state.counters["cand_pts"] = s.candidates / n;
    state.counters["map_pts"] = double(map.size());
    g_splits[name] = s;
}

void BM_QuasiSyntheticRoom3M(benchmark::State& state)
{
    static const map::LidarMap map = quasi::makeSyntheticRoom(3'000'000);
    runRenderBenchmark(state, map, roomPoses(), "synthetic room " + std::to_string(map.size()) + " points");
}
BENCHMARK(BM_QuasiSyntheticRoom3M)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);

void BM_QuasiMapFile(benchmark::State& state)
{
    static const map::LidarMap map = map::LidarMap::load(std::getenv("QUASILOC_BENCH_MAP"));
    static const std::vector<mrpt::poses::CPose3D> poses = [] {
        const core::Trajectory traj = core::readTum(std::getenv("QUASILOC_BENCH_TUM"));
        std::vector<mrpt::poses::CPose3D> p;
        const size_t step = std::max<size_t>(1, traj.poses.size() / 50);
        for (size_t i = 0; i < traj.poses.size(); i += step) p.push_back(traj.poses[i].pose);
        return p;
    }();
    runRenderBenchmark(state, map, poses, std::string("map file ") + std::getenv("QUASILOC_BENCH_MAP"));
}
}  // namespace

int main(int argc, char** argv)
{
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    // QUASILOC_BENCH_CV_THREADS=0 runs everything on the calling thread (its CPU time is then the work).
    if (const char* t = std::getenv("QUASILOC_BENCH_CV_THREADS")) cv::setNumThreads(std::atoi(t));
    if (std::getenv("QUASILOC_BENCH_MAP") && std::getenv("QUASILOC_BENCH_TUM"))
        benchmark::RegisterBenchmark("BM_QuasiMapFile", BM_QuasiMapFile)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime()
            ->MinTime(3.0);
    std::printf("bench_quasi: 752x480 EuRoC cam0 (radtan), %d OpenCV threads\n", cv::getNumThreads());
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();

    std::printf(
        "\nPer quasi-image, mean over the timed renders (ms). wall: elapsed time (the bound applies to it);\n"
        "cpu: CPU time of all threads (the work, insensitive to other processes competing for the cores)\n");
    std::printf("%-36s %-5s %8s %8s %8s %8s %8s %6s %4s\n", "map", "", "culling", "project", "complete", "encode",
                "total", "bound", "ok");
    for (const auto& [name, s] : g_splits)
    {
        const double n = std::max(1, s.n);
        std::printf("%-36s %-5s %8.3f %8.3f %8.3f %8.3f %8.3f %6.1f %4s\n", name.c_str(), "wall", s.culling / n,
                    s.projection / n, s.completion / n, s.encoding / n, s.total / n, kBoundMs,
                    s.total / n <= kBoundMs ? "yes" : "NO");
        std::printf("%-36s %-5s %8.3f %8.3f %8.3f %8.3f %8.3f\n", "", "cpu", s.cpu_culling / n, s.cpu_projection / n,
                    s.cpu_completion / n, s.cpu_encoding / n, s.cpu_total / n);
        std::printf(
            "%-36s points: candidates %.0f, projected %.0f; pixels: sparse %.0f, hidden (see-through) %.0f, "
            "completed %.0f (renders: %d)\n",
            "", s.candidates / n, s.projected / n, s.sparse / n, s.occluded / n, s.completed / n, s.n);
    }
    return 0;
}
