// bench_streamed_field: the streamed distance field on maps of continuous ground, 0.01 to 1 km2.
//
//     bench_streamed_field table [cache folder]        the whole table: one child process per row (honest peak RSS)
//     bench_streamed_field row <km2> <layout> [cache folder] [write]   one row; layout: streamed | sparse | index
//     bench_streamed_field save <km2> <map file>        the generated map, for bench_distance_field_openvdb
//
// The map: a square of `km2` with ground sampled every 10 cm (jittered, gently rolling), a building every 40 m
// (facades every 10 cm, up to 15 m, no roof: what a LiDAR on the street sees) and poles; about 1.3 x 10^8 points per
// km2. The walk: a camera 1.6 m above the ground on a circle of 15 m around the centre, 600 frames at 20 Hz
// (3.1 m/s). A frame: focus() at the camera, then 2000 value + gradient queries around it (80 % within 0.15 m of
// the ground up to 10 m away, 20 % anywhere within 10 m), then the rest of the 50 ms frame asleep, as a tracker
// would spend it on the rest of its work while the field's worker builds tiles on the other core.
// Printed per row: points, map generation, field load (a streamed field: the point index, or the cache's header and
// map hash; sparse: the whole build), peak RSS (getrusage, the map included), the field's memory at the end, the
// frames' query time (median and p90 of wall time, median CPU time of the process: the worker's included), the
// tiles built, read from the cache, evicted and built by a query itself.
// layout = index: the map and its visibility index only (map/visibility_index.h), to measure the index's memory.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <quasiloc/map/distance_field.h>
#include <quasiloc/map/visibility_index.h>
#include <random>
#include <string>
#include <thread>
#include <vector>

namespace
{
using namespace quasiloc;
using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
double processCpuS()
{
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}
double peakRssMb()
{
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_maxrss) / 1024.0;
}

float groundZ(float x, float y) { return 0.4f * std::sin(x / 23.f) * std::cos(y / 31.f); }

/** A deterministic value in [0, 1) for integer coordinates. */
float hash01(int64_t a, int64_t b, int64_t c)
{
    uint64_t h =
        uint64_t(a) * 0x9E3779B97F4A7C15ull ^ uint64_t(b) * 0xC2B2AE3D27D4EB4Full ^ uint64_t(c) * 0x165667B19E3779F9ull;
    h ^= h >> 29;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 32;
    return float(h >> 40) / float(1ull << 24);
}

constexpr float kCell = 40.f, kStep = 0.1f;
struct Building
{
    float x0, y0, x1, y1, height;
};
Building buildingOf(int cx, int cy)
{
    const float w = 10.f + 8.f * hash01(cx, cy, 1), d = 8.f + 8.f * hash01(cx, cy, 2);
    const float x0 = float(cx) * kCell + 4.f + (kCell - 12.f - w) * hash01(cx, cy, 3);
    const float y0 = float(cy) * kCell + 4.f + (kCell - 12.f - d) * hash01(cx, cy, 4);
    return {x0, y0, x0 + w, y0 + d, 6.f + 9.f * hash01(cx, cy, 5)};
}

/** Calls add(x, y, z) for every point of the map of side `side` m (centred on 0). */
template <typename Add>
void generate(float side, Add&& add)
{
    const int cells = std::max(1, int(side / kCell));
    const float lo = -0.5f * side;
    const int n = int(side / kStep);
    for (int iy = 0; iy < n; ++iy)
        for (int ix = 0; ix < n; ++ix)
        {
            const float x = lo + (float(ix) + 0.4f * hash01(ix, iy, 7)) * kStep,
                        y = lo + (float(iy) + 0.4f * hash01(ix, iy, 8)) * kStep;
            const int cx = std::min(cells - 1, int((x - lo) / kCell)), cy = std::min(cells - 1, int((y - lo) / kCell));
            const Building b = buildingOf(cx, cy);
            const float bx = x - lo, by = y - lo;
            if (bx > b.x0 && bx < b.x1 && by > b.y0 && by < b.y1) continue;  // under a building
            add(x, y, groundZ(x, y) + 0.01f * (hash01(ix, iy, 9) - 0.5f));
        }
    for (int cy = 0; cy < cells; ++cy)
        for (int cx = 0; cx < cells; ++cx)
        {
            const Building b = buildingOf(cx, cy);
            const float z0 = groundZ(lo + b.x0, lo + b.y0);
            const auto wall = [&](float xa, float ya, float xb, float yb) {
                const float len = std::hypot(xb - xa, yb - ya);
                for (float s = 0; s < len; s += kStep)
                    for (float h = 0; h < b.height; h += kStep)
                        add(lo + xa + (xb - xa) * s / len, lo + ya + (yb - ya) * s / len, z0 + h);
            };
            wall(b.x0, b.y0, b.x1, b.y0), wall(b.x1, b.y0, b.x1, b.y1);
            wall(b.x1, b.y1, b.x0, b.y1), wall(b.x0, b.y1, b.x0, b.y0);
            for (int p = 0; p < 4; ++p)  // poles along the street
            {
                const float px = lo + float(cx) * kCell + 2.f + 9.f * float(p), py = lo + float(cy) * kCell + 2.f;
                for (float h = 0; h < 5.f; h += 0.05f)
                    for (int a = 0; a < 6; ++a)
                        add(px + 0.1f * std::cos(float(a)), py + 0.1f * std::sin(float(a)), groundZ(px, py) + h);
            }
        }
}

map::LidarMap makeMap(double km2)
{
    const float side = float(std::sqrt(km2) * 1000.0);
    size_t count = 0;
    generate(side, [&](float, float, float) { ++count; });
    map::LidarMap m;
    m.reserve(count);
    generate(side, [&](float x, float y, float z) { m.addPoint(x, y, z, 0.5f); });
    return m;
}

struct Frame
{
    Eigen::Vector3f camera;
    std::vector<Eigen::Vector3f> queries;
};

std::vector<Frame> walk(int frames)
{
    std::vector<Frame> out(static_cast<size_t>(frames));
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> unit(0, 1), sym(-1, 1);
    std::normal_distribution<float> near(0, 0.15f);
    for (int f = 0; f < frames; ++f)
    {
        const float a = 2.f * float(M_PI) * float(f) / float(frames);
        Frame& fr = out[size_t(f)];
        fr.camera = {15.f * std::cos(a), 15.f * std::sin(a), 0};
        fr.camera.z() = groundZ(fr.camera.x(), fr.camera.y()) + 1.6f;
        for (int q = 0; q < 2000; ++q)
        {
            const float r = 10.f * std::sqrt(unit(rng)), t = 2.f * float(M_PI) * unit(rng);
            Eigen::Vector3f p = fr.camera + Eigen::Vector3f(r * std::cos(t), r * std::sin(t), 0);
            if (q % 5 == 4)
                p = fr.camera + 10.f * Eigen::Vector3f(sym(rng), sym(rng), sym(rng)) / std::sqrt(3.f);
            else
                p.z() = groundZ(p.x(), p.y()) + near(rng);
            fr.queries.push_back(p);
        }
    }
    return out;
}

double percentile(std::vector<double> v, double q)
{
    std::sort(v.begin(), v.end());
    return v.empty() ? 0 : v[size_t(q * double(v.size() - 1))];
}

int row(double km2, const std::string& layout, const std::string& cache, bool write_cache)
{
    const auto t0 = Clock::now();
    const map::LidarMap m = makeMap(km2);
    const double generate_s = seconds(t0);
    if (layout == "index")
    {
        const auto t1 = Clock::now();
        const map::VisibilityIndex index(m, map::VisibilityIndex::Options{});
        const double index_s = seconds(t1);
        const double bytes = double(index.size()) * (4 * sizeof(float) + sizeof(uint32_t));
        std::printf("| %.2f | %zu | visibility index | %.1f s | %.2f s | %.0f MB | index %.0f MB (%zu blocks) |\n", km2,
                    m.size(), generate_s, index_s, peakRssMb(), bytes / 1048576.0, index.numBlocks());
        return 0;
    }
    map::DistanceFieldOptions o;  // as GeometricLocalizer::buildField makes it
    o.margin_m = 1.0;
    o.layout = layout == "sparse" ? map::DistanceFieldLayout::Sparse : map::DistanceFieldLayout::Streamed;
    o.tile_cache = cache;
    const double cpu0 = processCpuS();
    const auto t1 = Clock::now();
    const map::DistanceField field = map::DistanceField::build(m, o, "generated map");
    if (write_cache) field.writeAllTiles();
    const double load_s = seconds(t1), load_cpu_s = processCpuS() - cpu0;
    const std::vector<Frame> frames = walk(600);
    const auto t2 = Clock::now();
    field.focus(frames[0].camera);
    field.waitForFocus();
    const double first_s = seconds(t2);
    std::vector<double> wall_ms, cpu_ms;
    double checksum = 0;
    Eigen::Vector3f g;
    auto next = Clock::now();
    for (const Frame& f : frames)
    {
        next += std::chrono::milliseconds(50);
        const double c = processCpuS();
        const auto t = Clock::now();
        field.focus(f.camera);
        for (const auto& p : f.queries) checksum += field.distance(p, g);
        wall_ms.push_back(1e3 * seconds(t));
        std::this_thread::sleep_until(next);
        cpu_ms.push_back(1e3 * (processCpuS() - c));  // the frame's 50 ms: queries and the worker's builds
    }
    const map::DistanceField::StreamStats s = field.streamStats();
    std::printf(
        "| %.2f | %zu | %s%s | %.1f s | %.2f s (CPU %.2f s) | %.2f s | %.0f MB | %.0f MB | %.3f / %.3f ms | "
        "%.2f ms | %zu / %zu / %zu / %zu | %.4f |\n",
        km2, m.size(), layout.c_str(), cache.empty() ? "" : (write_cache ? ", cache written whole" : ", cache"),
        generate_s, load_s, load_cpu_s, first_s, peakRssMb(), double(field.memoryBytes()) / 1048576.0,
        percentile(wall_ms, 0.5), percentile(wall_ms, 0.9), percentile(cpu_ms, 0.5), s.built, s.read, s.evicted,
        s.synchronous, checksum / double(frames.size() * 2000));
    return 0;
}

int runChild(const std::vector<std::string>& args)
{
    std::fflush(stdout);
    const pid_t pid = fork();
    if (pid == 0)
    {
        std::vector<char*> argv;
        for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        execv("/proc/self/exe", argv.data());
        _exit(127);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
}
}  // namespace

int main(int argc, char** argv)
{
    const std::string mode = argc > 1 ? argv[1] : "";
    try
    {
        if (mode == "row" && argc >= 4)
            return row(std::stod(argv[2]), argv[3], argc > 4 ? argv[4] : "",
                       argc > 5 && std::string(argv[5]) == "write");
        if (mode == "save" && argc == 4)
        {
            const map::LidarMap m = makeMap(std::stod(argv[2]));
            m.save(argv[3]);
            std::cout << "wrote " << m.size() << " points to " << argv[3] << "\n";
            return 0;
        }
        if (mode == "table")
        {
            const std::string cache = argc > 2 ? argv[2] : "/tmp/bench_streamed_field_cache";
            std::printf(
                "| km2 | points | layout | map generation | field load | first focus ready | peak RSS | field "
                "memory at the end | query time per frame, median / p90 (wall) | CPU per 50 ms frame, median "
                "| tiles built / read / evicted / by a query | mean distance |\n|---|---|---|---|---|---|---|---|"
                "---|---|---|---|\n");
            int failures = 0;
            for (const char* km2 : {"0.01", "0.1", "1"})
            {
                const std::string dir = cache + "/" + km2;
                std::filesystem::remove_all(dir);
                std::string self = argv[0];
                failures += runChild({self, "row", km2, "streamed"}) != 0;
                failures += runChild({self, "row", km2, "streamed", dir}) != 0;  // written through
                failures += runChild({self, "row", km2, "streamed", dir}) != 0;  // read back
            }
            failures += runChild({argv[0], "row", "0.01", "sparse"}) != 0;
            for (const char* km2 : {"0.01", "0.1", "1"}) failures += runChild({argv[0], "row", km2, "index"}) != 0;
            return failures == 0 ? 0 : 1;
        }
    }
    catch (const std::exception& e)
    {
        std::cerr << "bench_streamed_field: error: " << e.what() << "\n";
        return 1;
    }
    std::cerr << "usage: bench_streamed_field table [cache folder] | row <km2> <streamed|sparse|index> [cache folder] "
                 "[write] | save <km2> <map file>\n";
    return 2;
}
