// bench_place_retrieval: global localization by geometry with no initial guess on the large test world
// (docs/large_maps.md, docs/place_retrieval.md), with place retrieval and, for comparison, without it.
//
//     bench_place_retrieval <large_world.ini> [--set Section.key=value]... [--places N] [--baseline N] [--seed S]
//
// The world map is [LargeWorld] output. Each query is a place in one of the world's rooms other than the centre
// one, chosen at random: the room is rebuilt as sim-large-world built it (same seed, same yaw), a camera pose is
// drawn near one of its free positions (random heading, pitch -25..10 deg, roll +-5 deg), the simulator renders
// the stereo pair there (sim::StereoRenderer: textures, lighting, sensor noise) and SGBM makes the query points
// (StereoCloud), as on a robot. Gravity is given 2 deg off. Printed: one row per query, then recall@0.1/0.3/1 m,
// median and p90 wall and CPU time per attempt (stereo matching included), and the retrieval's recall@K (a
// retrieved place within retrieval_radius_m + 0.25 m of the camera, at a heading within
// retrieval_yaw_margin_deg + 5 deg of the camera's). --baseline N runs the first N queries without retrieval too.
// Options: [GeometricLocalization] (the localizer), [LargeWorld] [World] [Lidar] (the world, as sim-large-world).
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/reloc/geometric_localizer.h>
#include <quasiloc/sim/large_world.h>
#include <quasiloc/sim/lidar_sampler.h>
#include <quasiloc/sim/stereo_renderer.h>
#include <quasiloc/sim/world_builder.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <random>

namespace
{
using namespace quasiloc;
using Clock = std::chrono::steady_clock;

const char* kUsage =
    "usage: bench_place_retrieval <large_world.ini> [--set Section.key=value]... [--places N] [--baseline N] "
    "[--seed S]";

double cpuSeconds()
{
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double seconds(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct Query
{
    int room = 0;
    Eigen::Isometry3d T_world_cam;
    cv::Mat left, right;
};

struct Attempt
{
    bool localized = false;
    double error_m = 1e9, error_deg = 1e9, wall_s = 0, cpu_s = 0;
    size_t candidates = 0;
    std::string reason;
};

/** Azimuth of the camera's viewing direction (as SearchSphere::headingAdmits measures headings). */
double azimuth(const Eigen::Matrix3d& R)
{
    Eigen::Vector3d d = R.col(2);
    if (std::hypot(d.x(), d.y()) < 0.3) d = R.col(0);
    return std::atan2(d.y(), d.x());
}

/** The room of cell `k` (0-based, the order sim-large-world adds them) and its pose in the world. */
struct Room
{
    sim::World world;
    Eigen::Isometry3d T_world_room = Eigen::Isometry3d::Identity();
    std::vector<mrpt::poses::CPose3D> free_views;
};

Room rebuildRoom(int k, const sim::LargeWorldOptions& o, const sim::WorldOptions& world, const sim::LidarOptions& lidar,
                 const Eigen::Vector2d& base_centre)
{
    const int half = o.grid_cells / 2;
    int done = 0, cell_x = 0, cell_y = 0;
    for (int gy = -half; gy <= half; ++gy)
        for (int gx = -half; gx <= half; ++gx)
        {
            if (gx == 0 && gy == 0) continue;
            if (done++ == k) cell_x = gx, cell_y = gy;
        }
    Room room;
    const uint64_t seed = uint64_t(o.seed) + uint64_t(k);
    sim::WorldOptions w = world;
    w.world = (k % 2 == 0) ? sim::ViconRoom::v2 : sim::ViconRoom::v1;
    room.world = sim::buildWorld(w, o.shared_dir, seed,
                                 sim::loadRoomTrajectoryPositions(o.shared_dir, k % 2 == 0 ? "v2" : "v1"));
    const map::LidarMap room_map = sim::sampleSurveyMap(room.world, lidar, seed);
    std::mt19937_64 rng(seed);
    const double yaw = std::uniform_real_distribution<double>(0, 2 * M_PI)(rng);
    const map::MapBounds b = room_map.bounds();
    const Eigen::Vector3d c(0.5 * (b.min.x() + b.max.x()), 0.5 * (b.min.y() + b.max.y()), 0);
    const Eigen::Vector2d centre = base_centre + o.spacing_m * Eigen::Vector2d(cell_x, cell_y);
    // p_world = centre + Rz(yaw) (p_room - c), in float as sim-large-world computes it (well below a millimetre).
    room.T_world_room.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    room.T_world_room.translation() = Eigen::Vector3d(centre.x(), centre.y(), 0) - room.T_world_room.linear() * c;
    reloc::ViewSamplingOptions vs;
    vs.num_headings = 1;
    room.free_views = reloc::sampleViewpoints(room_map, vs);
    return room;
}

Attempt run(const reloc::GeometricLocalizer& localizer, const Query& q, const Eigen::Vector3d& up_cam)
{
    Attempt a;
    const auto t0 = Clock::now();
    const double c0 = cpuSeconds();
    const reloc::GeometricLocalization r = localizer.localize(q.left, q.right, up_cam);
    a.wall_s = seconds(t0);
    a.cpu_s = cpuSeconds() - c0;
    a.localized = r.localized;
    a.reason = r.reason;
    a.candidates = r.candidates;
    a.error_m = core::translationDistance(r.T_world_cam, q.T_world_cam);
    a.error_deg = core::rotationDistanceRad(r.T_world_cam, q.T_world_cam) * 180 / M_PI;
    return a;
}

double quantile(std::vector<double> v, double q)
{
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(q * double(v.size())))];
}

void printSummary(const std::string& name, const std::vector<Attempt>& attempts)
{
    std::vector<double> wall, cpu;
    int r01 = 0, r03 = 0, r1 = 0;
    for (const auto& a : attempts)
    {
        wall.push_back(a.wall_s);
        cpu.push_back(a.cpu_s);
        r01 += a.localized && a.error_m <= 0.1;
        r03 += a.localized && a.error_m <= 0.3;
        r1 += a.localized && a.error_m <= 1.0;
    }
    const double n = double(attempts.size());
    std::printf("| %s | %zu | %.0f %% | %.0f %% | %.0f %% | %.2f / %.2f s | %.2f / %.2f s |\n", name.c_str(),
                attempts.size(), 100 * r01 / n, 100 * r03 / n, 100 * r1 / n, quantile(wall, 0.5), quantile(wall, 0.9),
                quantile(cpu, 0.5), quantile(cpu, 0.9));
}

int bench(const core::CommandLine& cmd)
{
    int places = 20, baseline = 0, seed = 1;
    for (size_t i = 0; i + 1 < cmd.flags.size(); i += 2)
    {
        const std::string& f = cmd.flags[i];
        const int v = std::stoi(cmd.flags[i + 1]);
        if (f == "--places")
            places = v;
        else if (f == "--baseline")
            baseline = v;
        else if (f == "--seed")
            seed = v;
        else
            throw core::InputError("command line", "unknown flag " + f);
    }
    core::require(cmd.flags.size() % 2 == 0, "command line", "a flag without its value");
    const auto cfg = core::loadConfig(cmd);
    const std::string name = cmd.config_path;
    sim::LargeWorldOptions lw;
    sim::WorldOptions world;
    sim::LidarOptions lidar;
    reloc::GeometricLocalizationOptions go;
    core::loadOptionsChecked(lw, cfg, "LargeWorld", name);
    core::loadOptionsChecked(world, cfg, "World", name);
    core::loadOptionsChecked(lidar, cfg, "Lidar", name);
    core::loadOptionsChecked(go, cfg, "GeometricLocalization", name);

    auto t0 = Clock::now();
    const map::LidarMap base = map::LidarMap::load(lw.base_map);
    const map::MapBounds bb = base.bounds();
    const Eigen::Vector2d base_centre(0.5 * (bb.min.x() + bb.max.x()), 0.5 * (bb.min.y() + bb.max.y()));
    const map::LidarMap map = map::LidarMap::load(lw.output);
    std::cout << "map " << lw.output << ": " << map.size() << " points, loaded in " << seconds(t0) << " s" << std::endl;
    const std::string calib = lw.shared_dir + "/data/euroc/calib/";
    const core::StereoRig rig = core::StereoRig::fromEuroc(calib + "cam0_sensor.yaml", calib + "cam1_sensor.yaml");
    t0 = Clock::now();
    const auto field = reloc::GeometricLocalizer::buildField(map, go, lw.output);
    const auto index = std::make_shared<const map::VisibilityIndex>(map, map::VisibilityIndex::Options{});
    std::cout << "distance field and visibility index " << seconds(t0) << " s" << std::endl;
    t0 = Clock::now();
    const reloc::GeometricLocalizer with(map, rig, go, field, index, lw.output);
    std::cout << "localizer with retrieval: " << with.positions() << " candidate positions, "
              << (with.places() ? with.places()->size() : 0) << " places (profiles " << with.placesBuildSeconds()
              << " s), set up in " << seconds(t0) << " s" << std::endl;
    core::require(with.places() != nullptr, name,
                  "no place retrieval on this map: [GeometricLocalization] retrieval_min_positions is above its " +
                      std::to_string(with.positions()) + " candidate positions");
    std::unique_ptr<reloc::GeometricLocalizer> without;
    if (baseline > 0)
    {
        reloc::GeometricLocalizationOptions whole = go;
        whole.retrieval_min_positions = std::numeric_limits<int>::max();
        whole.places_file.clear();
        without = std::make_unique<reloc::GeometricLocalizer>(map, rig, whole, field, index, lw.output);
    }

    std::mt19937_64 rng{uint64_t(seed)};
    std::vector<int> rooms(size_t(lw.grid_cells * lw.grid_cells - 1));
    for (size_t k = 0; k < rooms.size(); ++k) rooms[k] = int(k);
    std::shuffle(rooms.begin(), rooms.end(), rng);
    const std::vector<size_t> ks{1, 10, 50, 100, 200, 500, 2000};
    std::vector<size_t> hits_at(ks.size(), 0);
    std::vector<Attempt> with_retrieval, whole_search, baseline_with;
    std::uniform_real_distribution<double> u(-1, 1);
    std::printf(
        "| query | room | localized | error m | error deg | candidates | wall s | CPU s | true place rank | "
        "without retrieval: error m, wall s |\n|---|---|---|---|---|---|---|---|---|---|\n");
    for (int qi = 0; qi < places; ++qi)
    {
        const int k = rooms[size_t(qi) % rooms.size()];
        const Room room = rebuildRoom(k, lw, world, lidar, base_centre);
        const mrpt::poses::CPose3D& v =
            room.free_views[std::uniform_int_distribution<size_t>(0, room.free_views.size() - 1)(rng)];
        const double heading = M_PI * u(rng), pitch = (-7.5 + 17.5 * u(rng)) * M_PI / 180;
        Eigen::Isometry3d T_room_cam = core::toIsometry(
            reloc::viewPose(v.x() + 0.12 * u(rng), v.y() + 0.12 * u(rng), v.z() + 0.15 * u(rng), heading, pitch));
        T_room_cam.linear() = T_room_cam.linear() *
                              Eigen::AngleAxisd(5 * M_PI / 180 * u(rng), Eigen::Vector3d::UnitZ()).toRotationMatrix();
        Query q;
        q.room = k;
        q.T_world_cam = room.T_world_room * T_room_cam;
        sim::StereoRenderer renderer(room.world, rig, sim::AppearanceOptions(), uint64_t(seed) * 1000 + uint64_t(qi));
        renderer.render({core::fromIsometry(T_room_cam)}, 0.0, uint64_t(qi), q.left, q.right);
        const Eigen::Vector3d up_true = q.T_world_cam.linear().transpose() * Eigen::Vector3d::UnitZ();
        const Eigen::Vector3d axis = up_true.unitOrthogonal();
        const Eigen::Vector3d up = Eigen::AngleAxisd(2 * M_PI / 180, axis) * up_true;

        // The retrieval's own recall: rank of the first retrieved place at the camera.
        const auto points = with.placeStereoPoints(q.left, q.right);
        const auto retrieved = with.retrieve(points, up, nullptr, 2000);
        const Eigen::Matrix3d R_level =
            Eigen::Quaterniond::FromTwoVectors(up.normalized(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
        int rank = -1;
        for (size_t j = 0; j < retrieved.size() && rank < 0; ++j)
        {
            const Eigen::Vector3d p = with.places()->positions[retrieved[j].place].cast<double>();
            const Eigen::Matrix3d R =
                Eigen::AngleAxisd(retrieved[j].yawRad(with.places()->descriptor.sectors), Eigen::Vector3d::UnitZ())
                    .toRotationMatrix() *
                R_level;
            const double dyaw = std::abs(std::remainder(azimuth(R) - azimuth(q.T_world_cam.linear()), 2 * M_PI));
            if ((p - q.T_world_cam.translation()).head<2>().norm() <= go.retrieval_radius_m + 0.25 &&
                dyaw * 180 / M_PI <= go.retrieval_yaw_margin_deg + 5)
                rank = int(j) + 1;
        }
        for (size_t j = 0; j < ks.size(); ++j) hits_at[j] += rank > 0 && size_t(rank) <= ks[j];

        const Attempt a = run(with, q, up);
        with_retrieval.push_back(a);
        std::string base_text = "-";
        if (without && qi < baseline)
        {
            const Attempt b = run(*without, q, up);
            whole_search.push_back(b);
            baseline_with.push_back(a);
            char buf[96];
            std::snprintf(buf, sizeof(buf), "%s %.3f, %.1f", b.localized ? "yes" : "no", b.error_m, b.wall_s);
            base_text = buf;
        }
        std::printf("| %d | %d | %s | %.3f | %.2f | %zu | %.2f | %.2f | %s | %s |%s\n", qi, k,
                    a.localized ? "yes" : "no", a.error_m, a.error_deg, a.candidates, a.wall_s, a.cpu_s,
                    rank > 0 ? std::to_string(rank).c_str() : "not retrieved", base_text.c_str(),
                    a.localized ? "" : (" " + a.reason).c_str());
        std::fflush(stdout);
    }
    std::printf(
        "\n| search | attempts | recall@0.1 m | recall@0.3 m | recall@1 m | wall median / p90 | CPU median / "
        "p90 |\n|---|---|---|---|---|---|---|\n");
    printSummary("with place retrieval", with_retrieval);
    if (!whole_search.empty())
    {
        printSummary("with place retrieval (the same queries as below)", baseline_with);
        printSummary("whole map, no retrieval", whole_search);
    }
    std::printf("\nretrieval recall (true place among the top K; the localizer takes K = retrieval_places = %d):",
                go.retrieval_places);
    for (size_t j = 0; j < ks.size(); ++j)
        std::printf(" @%zu %.0f %%", ks[j], 100.0 * double(hits_at[j]) / double(std::max(places, 1)));
    std::printf("\n");
    return 0;
}
}  // namespace

int main(int argc, char** argv) { return core::runProgram(argc, argv, kUsage, bench); }
