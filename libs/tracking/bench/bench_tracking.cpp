// bench_tracking: Google Benchmark of each stage of one tracked frame, at the sizes of a real run: the frames, map
// and calibration of a quasiloc-track configuration (default config.ini: the main job's simulated 752x480 EuRoC
// flight and its 2.25 M-point map; run `bash scripts/run.sh` or `build/bin/sim-rawlog config.ini` first).
//
//     bench_tracking [config.ini] [--set Section.key=value]... [--benchmark_filter=...] [other Google Benchmark flags]
//
// Stages (the tracker's order, tracker.h): IMU prediction, the camera edge field, the quasi-image render at the
// pose, the map edge model, the direct alignment from a pose 2 cm / 0.5 deg off, the stereo points of both images
// (descriptor matching) or of the left image guided by the dense disparity (guided matching), the dense stereo cloud
// (stereo_map_points = dense), and the whole Tracker::step (the window included: its share is the counter window_ms).
// Every benchmark cycles over the first [Bench] frames frames of the rawlog. The real EuRoC micro set: the same with
// the --set lines of scripts/real_micro.sh (docs/benchmarks.md).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/program_options.h>
#include <sstream>
#include <quasiloc/dataset/calibration.h>
#include <quasiloc/dataset/frame_source.h>
#include <quasiloc/estimation/direct_alignment.h>
#include <quasiloc/frontend/stereo_matcher.h>
#include <quasiloc/reloc/stereo_cloud.h>
#include <quasiloc/tracking/map_context.h>
#include <quasiloc/tracking/track_monitor.h>
#include <quasiloc/tracking/tracker.h>
#include <quasiloc/tracking/tracking_session.h>
#include <string>
#include <vector>

using namespace quasiloc;

namespace
{
constexpr size_t kFrames = 60;  // 3 s at 20 Hz: enough poses and images to average over

/** Everything the benchmarks share, loaded once from the configuration. */
struct Fixture
{
    tracking::SessionOptions options;
    std::unique_ptr<tracking::MapContext> context;
    dataset::SensorCalibration calibration;
    std::vector<dataset::StereoFrame> frames;  ///< with ground truth
};
Fixture* g_fixture = nullptr;

Fixture& fixture() { return *g_fixture; }

const dataset::StereoFrame& frameAt(size_t k) { return fixture().frames[k % fixture().frames.size()]; }

Eigen::Isometry3d truth(const dataset::StereoFrame& f) { return core::toIsometry(*f.T_world_cam0); }

/** The pose the direct alignment starts from: the truth moved by 2 cm and 0.5 deg (a typical IMU prediction). */
Eigen::Isometry3d perturbed(const Eigen::Isometry3d& T_world_cam)
{
    Eigen::Isometry3d d = Eigen::Isometry3d::Identity();
    d.translate(Eigen::Vector3d(0.012, -0.010, 0.012));
    d.rotate(Eigen::AngleAxisd(0.5 * M_PI / 180.0, Eigen::Vector3d(0.3, 0.9, 0.3).normalized()));
    return T_world_cam * d;
}

const estimation::DirectAlignmentOptions& directOptions() { return fixture().options.refinement.direct; }
const core::CameraModel& leftCamera() { return fixture().calibration.rig.left; }

void BM_ImuPrediction(benchmark::State& state)
{
    const estimation::ImuNoise noise = tracking::imuNoise(fixture().calibration.requireImu("bench_tracking"));
    size_t k = 1;
    for (auto _ : state)
    {
        const dataset::StereoFrame& f = frameAt(k++);
        if (f.index == 0) continue;
        std::vector<estimation::ImuMeasurement> samples;
        for (const auto& s : f.imu) samples.push_back({s.t, s.acc, s.gyro});
        estimation::ImuPreintegration imu(noise, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
        imu.integrateInterval(samples, samples.front().t - 1e-3, f.timestamp);
        benchmark::DoNotOptimize(imu.dt());
    }
}

void BM_CameraEdgeField(benchmark::State& state)
{
    size_t k = 0;
    for (auto _ : state) benchmark::DoNotOptimize(estimation::buildCameraEdgeField(directOptions(), frameAt(k++).left));
}

/** The completion radius of a render at 1/downscale of the camera's resolution, as MapRefiner::prepareDirect's. */
int completionRadius(int downscale) { return fixture().context->renderer().options().completionRadiusAt(downscale); }

/** Arguments: (1: the tracker's render, planes only, no encoding: map_points off; 0: the full quasi-image) and
 *  the resolution's divisor ([Tracking] model_downscale). */
void BM_Render(benchmark::State& state)
{
    const bool planes_only = state.range(0) != 0;
    const int downscale = int(state.range(1));
    const core::CameraModel camera = leftCamera().downscaled(downscale);
    quasi::QuasiImage q;
    size_t k = 0;
    for (auto _ : state)
        fixture().context->renderer().render(core::fromIsometry(perturbed(truth(frameAt(k++)))), camera, q,
                                             !planes_only, completionRadius(downscale));
    state.SetLabel(std::string(planes_only ? "planes only (tracker)" : "with encoding") + ", " +
                   std::to_string(camera.width) + "x" + std::to_string(camera.height));
}

/** A quasi-image at each frame's starting pose (rendered once, outside the timing), at 1/downscale resolution. */
std::vector<quasi::QuasiImage> renderAll(int downscale = 1)
{
    std::vector<quasi::QuasiImage> out(fixture().frames.size());
    for (size_t k = 0; k < out.size(); ++k)
        fixture().context->renderer().render(core::fromIsometry(perturbed(truth(frameAt(k)))),
                                             leftCamera().downscaled(downscale), out[k], true,
                                             completionRadius(downscale));
    return out;
}

/** Argument: the planes' resolution divisor ([Tracking] model_downscale). */
void BM_EdgeModel(benchmark::State& state)
{
    const int downscale = int(state.range(0));
    const std::vector<quasi::QuasiImage> qs = renderAll(downscale);
    const core::CameraModel camera = leftCamera().downscaled(downscale);
    size_t k = 0;
    size_t points = 0;
    for (auto _ : state)
    {
        const quasi::QuasiImage& q = qs[k % qs.size()];
        const auto model =
            estimation::buildDirectAlignmentModel(directOptions(), q.depth, q.reflectivity, q.valid, q.sparse, camera,
                                                  perturbed(truth(frameAt(k))), downscale);
        points += model.edge_points_world.size();
        ++k;
    }
    state.counters["edge_points"] = double(points) / double(std::max<size_t>(1, k));
}

void BM_DirectAlignment(benchmark::State& state)
{
    const std::vector<quasi::QuasiImage> qs = renderAll();
    std::vector<estimation::CameraEdgeField> fields;
    std::vector<estimation::DirectAlignmentModel> models;
    for (size_t k = 0; k < qs.size(); ++k)
    {
        fields.push_back(estimation::buildCameraEdgeField(directOptions(), frameAt(k).left));
        models.push_back(estimation::buildDirectAlignmentModel(directOptions(), qs[k].depth, qs[k].reflectivity,
                                                               qs[k].valid, qs[k].sparse, leftCamera(),
                                                               perturbed(truth(frameAt(k)))));
    }
    size_t k = 0;
    double error_cm = 0, iterations = 0;
    for (auto _ : state)
    {
        const size_t i = k++ % qs.size();
        Eigen::Isometry3d T = perturbed(truth(frameAt(i)));
        estimation::DirectAlignmentStats st;
        estimation::alignDirect(directOptions(), fields[i], leftCamera(), models[i], T, &st);
        error_cm += 100 * (T.translation() - truth(frameAt(i)).translation()).norm();
        iterations += st.iterations;
    }
    state.counters["error_cm"] = error_cm / double(std::max<size_t>(1, k));
    state.counters["iterations"] = iterations / double(std::max<size_t>(1, k));
}

void BM_StereoPoints(benchmark::State& state)
{
    frontend::Frontend frontend(fixture().options.frontend);
    const frontend::StereoMatcher matcher(fixture().calibration.rig, fixture().options.frontend.stereo);
    size_t k = 0, matches = 0;
    for (auto _ : state)
    {
        const dataset::StereoFrame& f = frameAt(k++);
        frontend::FrameFeatures left, right;
        frontend.extractPoints(f.left, cv::Mat(), left);
        frontend.extractPoints(f.right, cv::Mat(), right);
        matches += matcher.match(left.points, right.points).size();
    }
    state.counters["matches"] = double(matches) / double(std::max<size_t>(1, k));
}

/** Tracking.stereo_matching = guided: ORB on the left image only, the right match searched around the frame's
 *  dense disparity (computed beforehand, untimed: the frame computes it for the surface factor anyway). */
void BM_GuidedStereoPoints(benchmark::State& state)
{
    frontend::Frontend frontend(fixture().options.frontend);
    const reloc::StereoCloud cloud(fixture().calibration.rig, fixture().options.localization.stereo);
    const tracking::GuidedStereo guided(fixture().calibration.rig, cloud.rectification(),
                                        fixture().options.frontend.stereo, fixture().options.tracker.guided);
    std::vector<reloc::StereoDisparity> disparities;
    for (size_t i = 0; i < std::min(kFrames, fixture().frames.size()); ++i)
        disparities.push_back(cloud.disparity(frameAt(i).left, frameAt(i).right, "bench"));
    size_t k = 0, matches = 0;
    for (auto _ : state)
    {
        const size_t i = k++ % disparities.size();
        frontend::FrameFeatures left;
        frontend.extractPoints(frameAt(i).left, cv::Mat(), left);
        std::vector<cv::KeyPoint> right;
        matches += guided.match(left.points.keypoints, disparities[i], right).size();
    }
    state.counters["matches"] = double(matches) / double(std::max<size_t>(1, k));
}

void BM_DenseStereo(benchmark::State& state)
{
    const reloc::StereoCloud cloud(fixture().calibration.rig, fixture().options.localization.stereo);
    size_t k = 0, points = 0;
    for (auto _ : state)
    {
        const dataset::StereoFrame& f = frameAt(k++);
        points += cloud.compute(f.left, f.right, "bench").size();
    }
    state.counters["points"] = double(points) / double(std::max<size_t>(1, k));
}

/** BM_DenseStereo's two steps: the disparity (rectification, halving, SGBM), then its cloud (depth range, voxels). */
void BM_DenseDisparity(benchmark::State& state)
{
    const reloc::StereoCloud cloud(fixture().calibration.rig, fixture().options.localization.stereo);
    size_t k = 0;
    for (auto _ : state)
    {
        const dataset::StereoFrame& f = frameAt(k++);
        benchmark::DoNotOptimize(cloud.disparity(f.left, f.right, "bench"));
    }
}

void BM_DenseCloudPoints(benchmark::State& state)
{
    const reloc::StereoCloud cloud(fixture().calibration.rig, fixture().options.localization.stereo);
    std::vector<reloc::StereoDisparity> disparities;
    for (size_t i = 0; i < std::min(kFrames, fixture().frames.size()); ++i)
        disparities.push_back(cloud.disparity(frameAt(i).left, frameAt(i).right, "bench"));
    size_t k = 0, points = 0;
    for (auto _ : state) points += cloud.points(disparities[k++ % disparities.size()]).size();
    state.counters["points"] = double(points) / double(std::max<size_t>(1, k));
}

/** Tracker::step frame after frame from the ground truth at the first frame (restarted, untimed, at the end). */
void BM_TrackFrame(benchmark::State& state)
{
    Fixture& fx = fixture();
    const estimation::ImuNoise noise = tracking::imuNoise(fx.calibration.requireImu("bench_tracking"));
    tracking::Tracker tracker(fx.options.tracker, fx.options.refinement, fx.options.estimator, fx.options.reweighting,
                              fx.calibration.rig, noise, fx.context->renderer(), fx.options.frontend);
    if (fx.options.tracker.factors.stereo_map_factor)
        tracker.setMapDistanceField(fx.context->distanceField(fx.options.localization).get());
    // As TrackingSession does: the dense stereo of stereo_map_points = dense.
    const reloc::StereoCloud cloud(fx.calibration.rig, fx.options.localization.stereo);
    if (fx.options.tracker.factors.stereo_map_points == tracking::StereoMapPoints::Dense)
        tracker.setStereoCloud(&cloud);
    const auto restart = [&] {
        const dataset::StereoFrame &f0 = fx.frames[0], &f1 = fx.frames[1];
        const Eigen::Isometry3d T_body_cam = core::toIsometry(fx.calibration.rig.T_body_left);
        const Eigen::Vector3d v =
            ((truth(f1) * T_body_cam.inverse()).translation() - (truth(f0) * T_body_cam.inverse()).translation()) /
            (f1.timestamp - f0.timestamp);
        tracking::ImuBiasPrior biases;
        biases.gyro_bias = fx.calibration.requireImu("bench_tracking").gyroscope_bias;
        biases.acc_bias = fx.calibration.requireImu("bench_tracking").accelerometer_bias;
        tracker.initialize(f0.timestamp, truth(f0), v, biases, &f0);
    };
    restart();
    // The session's stereo gate: its bound and usual edge fit from the monitor's policy.
    std::ostringstream quiet;
    tracking::TrackMonitor monitor(fx.options.monitor, quiet, [](double, double) {});
    size_t k = 1, n = 0;
    double window = 0, solve = 0, marginal = 0, align = 0, edge_field = 0, visual = 0;
    for (auto _ : state)
    {
        const tracking::FrameReport r = tracker.step(fx.frames[k], monitor.stereoGate()).report;
        monitor.frameTracked(r);
        window += r.ms_window, align += r.ms_align, edge_field += r.ms_image, visual += r.ms_visual, ++n;
        solve += r.ms_window_solve, marginal += r.ms_window_marginal;
        if (++k == fx.frames.size())
        {
            state.PauseTiming();
            restart();
            k = 1;
            state.ResumeTiming();
        }
    }
    const double m = double(std::max<size_t>(1, n));
    state.counters["edge_field_ms"] = edge_field / m;
    state.counters["align_ms"] = align / m;
    state.counters["visual_ms"] = visual / m;
    state.counters["window_ms"] = window / m;
    state.counters["window_solve_ms"] = solve / m;
    state.counters["window_marginal_ms"] = marginal / m;
}

BENCHMARK(BM_ImuPrediction)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CameraEdgeField)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Render)->Args({0, 1})->Args({1, 1})->Args({1, 2})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EdgeModel)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DirectAlignment)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StereoPoints)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GuidedStereoPoints)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DenseStereo)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DenseDisparity)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DenseCloudPoints)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TrackFrame)->Unit(benchmark::kMillisecond)->MinTime(5.0);

std::unique_ptr<Fixture> load(const core::CommandLine& cmd)
{
    auto fx = std::make_unique<Fixture>();
    const auto cfg = core::loadConfig(cmd);
    fx->options.load(cfg, cmd.config_path);
    const tracking::TrackingRunOptions& t = fx->options.tracker;
    core::requireInputFiles(cmd.config_path, "Tracking",
                            {{"input_rawlog", t.input_rawlog},
                             {"calibration_ini", t.calibration_ini},
                             {"map_file", t.map_file},
                             {"groundtruth", t.groundtruth}});
    fx->context = std::make_unique<tracking::MapContext>(t.map_file, fx->options.quasi);
    fx->calibration = dataset::loadCalibration(t.calibration_ini);
    dataset::FrameSourceOptions so;
    so.groundtruth_tum = t.groundtruth;
    so.calibration_ini = t.calibration_ini;
    auto source = dataset::openRawlog(t.input_rawlog, so);
    for (dataset::StereoFrame f; fx->frames.size() < kFrames && source->next(f); f = dataset::StereoFrame{})
        if (f.T_world_cam0 && !f.imu.empty()) fx->frames.push_back(std::move(f));
    core::require(fx->frames.size() >= 10, t.input_rawlog, "fewer than 10 frames with ground truth and IMU samples");
    std::cout << "bench_tracking: " << fx->frames.size() << " frames of " << t.input_rawlog << ", map "
              << fx->context->map().summary() << std::endl;
    return fx;
}
}  // namespace

int main(int argc, char** argv)
{
    benchmark::Initialize(&argc, argv);  // takes its --benchmark_* flags out of argv
    std::vector<char*> args(argv, argv + argc);
    std::string default_config = "config.ini";
    if (argc < 2) args.push_back(default_config.data());
    return core::runProgram(int(args.size()), args.data(),
                            "usage: bench_tracking [config.ini] [--set Section.key=value]... [Google Benchmark flags]",
                            [](const core::CommandLine& cmd) {
                                const std::unique_ptr<Fixture> fx = load(cmd);
                                g_fixture = fx.get();
                                benchmark::RunSpecifiedBenchmarks();
                                benchmark::Shutdown();
                                g_fixture = nullptr;
                                return 0;
                            });
}
