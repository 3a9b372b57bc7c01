// quasiloc-track: tracks a stereo + IMU rawlog against a LiDAR map (libs/tracking/tracker.h).
//
//     quasiloc-track <config.ini> [--set Section.key=value]... [--print-timing]
//
// [Tracking]: the tracker's keys (tracker.h) and
//   input_rawlog, calibration_ini (dataset/calibration.h: rig + [imu], as sim-rawlog and euroc2rawlog write it), map_file,
//   groundtruth (TUM of T_world_cam0: initial state and the error table), output_dir, max_frames (0 = all),
//   write_scene (true: also scene.3Dscene).
// Other sections: [MapRefinement] [DirectAlignment] [Estimator] [Reweighting] [QuasiImage] and the front-end's.
// The initial state: [Tracking] init = groundtruth: the ground-truth pose of the first frame that has one, and the
// velocity from the ground truth of the first two frames; init = global: global localization by geometry of two
// frames and the IMU between them ([GeometricLocalization], tracking/global_initialization.h); the attempts are
// written to initialization.txt and the start's error against the ground truth is printed.
//
// Outputs in output_dir, all or nothing: trajectory.tum (T_world_cam0), diagnostics.csv (one row per frame),
// quasiloc-track.ini (effective configuration), initialization.txt (init = global), scene.3Dscene (map, ground truth in green, estimate in red: open with
// SceneViewer3D). Prints the error against ground truth and the time per frame.
#include <mrpt/config/CConfigFile.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/ini_read.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/dataset/calibration.h>
#include <quasiloc/dataset/frame_source.h>
#include <quasiloc/tracking/tracker.h>
#include <deque>
#include <sstream>

#include "background_search.h"
#include "global_start.h"
#include "run_log.h"
#include <memory>
#include "scene_export.h"

namespace
{
using namespace quasiloc;

/** [Tracking]: the tracker's options and the program's files. */
struct TrackRunOptions : public tracking::TrackerOptions
{
    std::string input_rawlog, calibration_ini, map_file, groundtruth, output_dir = "out/track";
    int max_frames = 0;
    bool write_scene = true;
    bool relocalize = true;  ///< with map_updates only
    /** The relocalization search (on its own thread) attempts only the newest of the frames waiting for it (real
     *  time; which frames depends on the machine's speed); false: every frame in order (reproducible, but the search
     *  can fall seconds behind: an attempt takes 0.2-0.6 s, 0.4-1.3 s over the whole map). */
    bool relocalize_latest_only = true;
    /** The relocalization searches near the last confirmed pose first (tracking::SearchPrior): within
     *  relocalize_near_m of it plus relocalize_speed_m_s per second since; relocalize_near_m = 0: the whole map.
     *  0.5 m (was 1 m): the search time grows with the sphere's volume (about 25,000 candidate positions took
     *  0.45-1.1 s at 1 m), and a confirmed pose is centimetres from the truth. */
    double relocalize_near_m = 0.5, relocalize_speed_m_s = 1.5;
    /** The relocalization restarts the tracker at the first fix, with the velocity the track had there (turned
     *  into the fix's frame, tracking::velocityAtFix), instead of waiting for a second fix 0.5 s later that gives it
     *  (init = global's pair, which also checks the fixes against the gyroscope): it saves the second attempt and the
     *  wait for its frame (the README's Known limitations gives the measured latencies). */
    bool relocalize_single_fix = true;
    /** A test of loss recovery ("kidnapping"): at this time after the start (< 0: never) the tracker is restarted
     *  kidnap_m to its side and kidnap_deg turned, with full confidence, as if it had silently gone wrong. */
    double kidnap_at_s = -1, kidnap_m = 1.0, kidnap_deg = 10;
    /** Loss detection by geometry (relocalize = true): every check_every frames, the share of the frame's stereo
     *  points the map explains at the tracked pose. At or above lost_explained_ratio the pose is confirmed. Below
     *  it the points are aligned to the map from the tracked pose (GlobalStarter::checkTrack): the check fails
     *  when that alignment explains lost_min_gain more of them (the geometry fits better elsewhere) or when the
     *  share is below lost_explained_floor; a view the map merely explains poorly, at the right pose, gains
     *  nothing from the alignment. A failed check is repeated on the next frame; two in a row: lost.
     *  Measured on four whole-flight runs (V1_02 twice, V2_01, V2_02; 774 checks, half-resolution stereo): at the
     *  tracked pose (error <= 6 cm) the share is 0.38-0.99; the alignment gains at most 0.035 except on the
     *  landing of V2_02 (the last 2.8 s: 0.38-0.40 explained 3.5 mm from the truth, the alignment slides 0.3 m
     *  and gains 0.07): the only 2 failed checks there. At poses put 1 m / 10 deg off the share is 0.02-0.67 and
     *  767 of 774 checks fail (0.3 m / 3 deg off: 755 of 774). A share below 0.7 alone made false losses on all
     *  six whole flights. Every 5 frames (was 10): a loss is noticed 0.25 s sooner for one more check of about
     *  15 ms every 10 frames. */
    int check_every = 5;
    double lost_explained_ratio = 0.7;
    double lost_min_gain = 0.05;
    double lost_explained_floor = 0.45;
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override
    {
        TrackerOptions::loadFromConfigFile(c, s);
        input_rawlog = c.read_string(s, "input_rawlog", input_rawlog);
        calibration_ini = c.read_string(s, "calibration_ini", calibration_ini);
        map_file = c.read_string(s, "map_file", map_file);
        groundtruth = c.read_string(s, "groundtruth", groundtruth);
        output_dir = c.read_string(s, "output_dir", output_dir);
        max_frames = core::readIniInt(c, s, "max_frames", max_frames);
        write_scene = core::readIniBool(c, s, "write_scene", write_scene);
        relocalize = core::readIniBool(c, s, "relocalize", relocalize);
        relocalize_latest_only = core::readIniBool(c, s, "relocalize_latest_only", relocalize_latest_only);
        relocalize_near_m = core::readIniDouble(c, s, "relocalize_near_m", relocalize_near_m);
        relocalize_speed_m_s = core::readIniDouble(c, s, "relocalize_speed_m_s", relocalize_speed_m_s);
        relocalize_single_fix = core::readIniBool(c, s, "relocalize_single_fix", relocalize_single_fix);
        kidnap_at_s = core::readIniDouble(c, s, "kidnap_at_s", kidnap_at_s);
        kidnap_m = core::readIniDouble(c, s, "kidnap_m", kidnap_m);
        kidnap_deg = core::readIniDouble(c, s, "kidnap_deg", kidnap_deg);
        check_every = core::readIniInt(c, s, "check_every", check_every);
        lost_explained_ratio = core::readIniDouble(c, s, "lost_explained_ratio", lost_explained_ratio);
        lost_min_gain = core::readIniDouble(c, s, "lost_min_gain", lost_min_gain);
        lost_explained_floor = core::readIniDouble(c, s, "lost_explained_floor", lost_explained_floor);
    }
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override
    {
        TrackerOptions::saveToConfigFile(c, s);
        c.write(s, "input_rawlog", input_rawlog);
        c.write(s, "calibration_ini", calibration_ini);
        c.write(s, "map_file", map_file);
        c.write(s, "groundtruth", groundtruth);
        c.write(s, "output_dir", output_dir);
        c.write(s, "max_frames", max_frames);
        c.write(s, "write_scene", write_scene ? "true" : "false");
        c.write(s, "relocalize", relocalize ? "true" : "false");
        c.write(s, "relocalize_latest_only", relocalize_latest_only ? "true" : "false");
        c.write(s, "relocalize_near_m", relocalize_near_m);
        c.write(s, "relocalize_speed_m_s", relocalize_speed_m_s);
        c.write(s, "relocalize_single_fix", relocalize_single_fix ? "true" : "false");
        c.write(s, "kidnap_at_s", kidnap_at_s);
        c.write(s, "kidnap_m", kidnap_m);
        c.write(s, "kidnap_deg", kidnap_deg);
        c.write(s, "check_every", check_every);
        c.write(s, "lost_explained_ratio", lost_explained_ratio);
        c.write(s, "lost_min_gain", lost_min_gain);
        c.write(s, "lost_explained_floor", lost_explained_floor);
    }
};

/** The tracker's IMU model and the biases' prior from the calibration's [imu] (dataset/calibration.h). */
estimation::ImuNoise imuNoise(const dataset::ImuCalibration& c)
{
    estimation::ImuNoise n;
    n.gyro_noise_density = c.gyroscope_noise_density;
    n.acc_noise_density = c.accelerometer_noise_density;
    n.gyro_random_walk = c.gyroscope_random_walk;
    n.acc_random_walk = c.accelerometer_random_walk;
    n.gravity_m_s2 = c.gravity_m_s2;
    return n;
}

tracking::ImuBiasPrior calibrationBiasPrior(const dataset::ImuCalibration& c)
{
    tracking::ImuBiasPrior p;
    p.gyro_bias = c.gyroscope_bias;
    p.acc_bias = c.accelerometer_bias;
    p.gyro_sigma = c.gyroscope_bias_sigma;
    p.acc_sigma = c.accelerometer_bias_sigma;
    p.source = "calibration";
    return p;
}

std::string describe(const tracking::ImuBiasPrior& p)
{
    std::ostringstream s;
    s.precision(4);
    s << "gyroscope bias [" << p.gyro_bias.transpose() << "] +- " << p.gyro_sigma << " rad/s, accelerometer bias ["
      << p.acc_bias.transpose() << "] +- " << p.acc_sigma << " m/s^2 (" << p.source << ")";
    return s.str();
}

const char* kUsage =
    "usage: quasiloc-track <config.ini> [--set Section.key=value]... [--print-timing]\n"
    "Tracks a stereo + IMU rawlog against a LiDAR map; writes trajectory.tum, diagnostics.csv and the effective\n"
    "configuration into [Tracking] output_dir (see apps/quasiloc-track/main.cpp).";

int run(const core::CommandLine& cmd)
{
    const auto cfg = core::loadConfig(cmd);
    const std::string name = cmd.config_path;
    TrackRunOptions o;
    core::loadOptionsChecked(o, cfg, "Tracking", name);
    o.check(name);
    core::require(o.check_every >= 1, name + ": [Tracking] check_every", "must be >= 1");
    core::require(o.relocalize_near_m >= 0, name + ": [Tracking] relocalize_near_m", "must be >= 0 (0: the whole map)");
    core::require(o.relocalize_speed_m_s >= 0, name + ": [Tracking] relocalize_speed_m_s", "must be >= 0");
    core::require(o.lost_explained_ratio >= 0 && o.lost_explained_ratio < 1, name + ": [Tracking] lost_explained_ratio",
                  "must be in [0, 1)");
    core::require(o.lost_min_gain > 0, name + ": [Tracking] lost_min_gain", "must be > 0");
    core::require(o.lost_explained_floor >= 0 && o.lost_explained_floor <= o.lost_explained_ratio,
                  name + ": [Tracking] lost_explained_floor", "must be in [0, lost_explained_ratio]");
    core::requireInputFiles(name, "Tracking",
                            {{"input_rawlog", o.input_rawlog}, {"calibration_ini", o.calibration_ini},
                             {"map_file", o.map_file}, {"groundtruth", o.groundtruth}});
    estimation::MapRefinementOptions ro;
    core::loadOptionsChecked(ro.direct, cfg, "DirectAlignment", name);
    core::loadOptionsChecked(ro, cfg, "MapRefinement", name);
    ro.check(name);
    estimation::EstimatorOptions eo;
    core::loadOptionsChecked(eo, cfg, "Estimator", name);
    eo.check(name);
    estimation::ReweightingOptions rw;
    core::loadOptionsChecked(rw, cfg, "Reweighting", name);
    rw.check(name);
    quasi::QuasiOptions qo;
    core::loadOptionsChecked(qo, cfg, "QuasiImage", name);
    qo.check(name);
    frontend::FrontendOptions fo;
    fo.load(cfg, name);

    const map::LidarMap map = map::LidarMap::load(o.map_file);
    dataset::FrameSourceOptions so;
    so.groundtruth_tum = o.groundtruth;
    so.calibration_ini = o.calibration_ini;
    auto source = dataset::openRawlog(o.input_rawlog, so);
    quasi::QuasiRenderer renderer(map, qo);
    frontend::Frontend frontend(fo);
    const dataset::SensorCalibration calibration = dataset::loadCalibration(o.calibration_ini);
    const dataset::ImuCalibration& imu_calibration = calibration.requireImu(o.calibration_ini);
    const estimation::ImuNoise imu_noise = imuNoise(imu_calibration);
    tracking::Tracker tracker(o, ro, eo, rw, source->rig(), imu_noise, renderer, frontend);
    std::cout << "map " << map.summary() << "\n" << source->description() << "\nmap term: " << tracker.mapTerm()
              << (o.map_term == "auto" ? " (auto: the map's reflectivity " : "")
              << (o.map_term == "auto" ? (tracker.mapTerm() == "none" ? "is constant)" : "varies)") : "") << std::endl;

    // The start: given by the ground truth, or found by global localization (init = global).
    const Eigen::Isometry3d T_body_cam = core::toIsometry(source->rig().T_body_left);
    dataset::StereoFrame f0;
    std::deque<dataset::StereoFrame> queued;  // frames read during the initialisation, still to be tracked
    reloc::GeometricLocalizationOptions go;
    core::loadOptionsChecked(go, cfg, "GeometricLocalization", name);
    go.check(name);
    Eigen::Isometry3d T_world_cam_start;
    std::unique_ptr<app::GlobalStarter> starter;  // global localization by geometry: start and relocalization
    std::unique_ptr<reloc::StereoCloud> stereo_cloud;  // stereo_map_points = dense
    // Relocalization is a use of the map: the no-map baselines (map_updates = false) stay pure.
    const bool relocalize = o.relocalize && o.map_updates;
    // The relocalization search runs beside the tracker (background_search.h): its refiner renders with a
    // renderer of its own (the same visibility index).
    std::unique_ptr<quasi::QuasiRenderer> search_renderer;
    if (relocalize) search_renderer = std::make_unique<quasi::QuasiRenderer>(map, renderer.visibilityIndex(), qo);
    if (o.init == "global" || relocalize || (o.stereo_map_factor && o.map_updates))
    {
        starter = std::make_unique<app::GlobalStarter>(map, source->rig(), o, go, ro,
                                                       search_renderer ? *search_renderer : renderer, frontend,
                                                       T_body_cam, imu_noise, o.map_file);
        if (o.stereo_map_factor) tracker.setMapDistanceField(&starter->field());
        if (o.stereo_map_points == "dense")
        {
            stereo_cloud = std::make_unique<reloc::StereoCloud>(source->rig(), go.stereo);
            tracker.setStereoCloud(stereo_cloud.get());
        }
        starter->setBiasPrior(calibrationBiasPrior(imu_calibration));
    }
    tracking::ImuBiasPrior start_biases;
    if (o.init == "groundtruth")
    {
        // The first two frames with ground truth give the initial pose and velocity.
        dataset::StereoFrame f1;
        // The IMU samples up to the first frame with ground truth: a platform that stood still over them gives its
        // gyroscope bias.
        tracking::StaticInitializer still(imu_calibration.gyroscope_noise_density);
        while (source->next(f0))
        {
            still.add(f0.imu);
            if (f0.T_world_cam0) break;
        }
        core::require(bool(f0.T_world_cam0), o.input_rawlog, "no frame with a ground-truth pose");
        core::require(source->next(f1) && f1.T_world_cam0, o.input_rawlog, "the second frame has no ground-truth pose");
        const Eigen::Vector3d p0 = (core::toIsometry(*f0.T_world_cam0) * T_body_cam.inverse()).translation();
        const Eigen::Vector3d p1 = (core::toIsometry(*f1.T_world_cam0) * T_body_cam.inverse()).translation();
        T_world_cam_start = core::toIsometry(*f0.T_world_cam0);
        start_biases = o.static_initialization
                           ? tracking::withStaticEstimate(calibrationBiasPrior(imu_calibration), still.estimate())
                           : calibrationBiasPrior(imu_calibration);
        tracker.initialize(f0.timestamp, T_world_cam_start, (p1 - p0) / (f1.timestamp - f0.timestamp), start_biases,
                           &f0);
        queued.push_back(std::move(f1));
    }
    else
    {
        auto found = starter->find([&](dataset::StereoFrame& out) { return source->next(out); }, "init");
        core::require(found.has_value(), o.input_rawlog,
                      "global initialisation found no start: no two frames localized by geometry and agreed with the "
                      "IMU (see the printed attempts)");
        auto& start = *found;
        f0 = std::move(start.anchor);
        T_world_cam_start = start.T_world_cam0;
        start_biases = start.biases;
        tracker.initializeFromGlobal(f0.timestamp, T_world_cam_start, *start.v_world, start_biases,
                                     &f0);  // a pair: always has a velocity
        for (auto& p : start.pending) queued.push_back(std::move(p));
    }
    dataset::StereoFrame f;
    auto nextFrame = [&](dataset::StereoFrame& out) {
        if (queued.empty()) return source->next(out);
        out = std::move(queued.front());
        queued.pop_front();
        return true;
    };
    core::require(nextFrame(f), o.input_rawlog, "no frame after the initial one");
    std::cout << "IMU biases at the start: " << describe(start_biases) << std::endl;

    app::RunLog log;
    log.addStart(f0, T_world_cam_start);
    int relocalizations = 0, losses = 0, withdrawn = 0;
    // Time the track went unverified: from the last frame whose pose the stereo geometry confirmed (a check that
    // passed, or a start) to the start of the relocalization that followed a loss (or the fixes that confirmed the
    // track after all): the stretch of the output with unconfirmed poses. The fix is found later, on a frame the
    // tracker reaches while the search works (the wait: it depends on the machine's speed, and the replay runs
    // faster than real time when a frame takes less than the camera's period).
    double last_verified_t = f0.timestamp, longest_unverified_s = 0, longest_wait_s = 0;
    bool kidnapped = false;
    int failed_checks = 0;  // consecutive failed geometry checks (TrackRunOptions::check_every)
    size_t n = 1;
    std::optional<app::BackgroundSearch> search;
    if (starter && relocalize) search.emplace(*starter, o.relocalize_latest_only);
    // Frames tracked since the search began, with the track's biases at each: after a restart at a fix the ones
    // after it are tracked again, from the biases the track had at the fix.
    std::deque<std::pair<dataset::StereoFrame, estimation::FrameState>> since_loss;
    // Two fixes agreed with the IMU. If they agree with the track too, the loss is withdrawn; otherwise the tracker
    // restarts at the first fix and the frames since are tracked again from there. Returns true on a restart.
    auto settle = [&](const tracking::GlobalInitialState& found, double t_now) {
        const double t_fix = found.anchor.timestamp;
        longest_unverified_s = std::max(longest_unverified_s, t_fix - last_verified_t);
        longest_wait_s = std::max(longest_wait_s, t_now - last_verified_t);
        const auto tracked = log.poseAt(t_fix);
        const bool agrees = tracked && core::translationDistance(*tracked, found.T_world_cam0) <= o.max_correction_m &&
                            core::rotationDistanceRad(*tracked, found.T_world_cam0) * 180 / M_PI <= o.max_correction_deg;
        std::cout << "relocalization at t " << std::fixed << std::setprecision(3) << t_fix << ": unverified since t "
                  << last_verified_t << ", found at t " << t_now << "; "
                  << (agrees ? "the fixes confirm the track: loss withdrawn" : "restarted") << std::endl;
        last_verified_t = t_fix;
        if (agrees)
        {
            ++withdrawn;
            since_loss.clear();
            return false;
        }
        ++relocalizations;
        estimation::FrameState track_at_fix = tracker.state();
        for (const auto& [frame, state] : since_loss)
            if (frame.timestamp <= t_fix) track_at_fix = state;
        // A single fix brings no velocity: the track's, turned into the fix's frame.
        const Eigen::Vector3d v_world =
            found.v_world ? *found.v_world
                          : tracking::velocityAtFix(found.T_world_cam0, T_body_cam, track_at_fix.T_map_body,
                                                    track_at_fix.v_map);
        // The biases the track had at the fix, with its present uncertainty about them.
        tracking::ImuBiasPrior biases = tracker.biasPrior();
        biases.gyro_bias = track_at_fix.gyro_bias;
        biases.acc_bias = track_at_fix.acc_bias;
        tracker.initializeFromGlobal(t_fix, found.T_world_cam0, v_world, biases, &found.anchor);
        log.rewindTo(t_fix);
        log.addStart(found.anchor, found.T_world_cam0);
        for (auto it = since_loss.rbegin(); it != since_loss.rend(); ++it)
            if (it->first.timestamp > t_fix)
            {
                queued.push_front(std::move(it->first));
                --n;  // tracked again
            }
        since_loss.clear();
        return true;
    };
    bool have_frame = true;
    while (have_frame)
    {
        const tracking::FrameReport r = tracker.track(f);
        ++n;
        double explained = NAN, ms_check = 0, ms_search = 0;
        const bool searching = search && search->searching();
        const bool check_due = n % size_t(o.check_every) == 0 || failed_checks > 0;
        if (search && check_due && !searching)
        {
            const auto t_check = std::chrono::steady_clock::now();
            const auto c = starter->checkTrack(f, r.T_world_cam0, o.lost_explained_ratio);
            explained = c.explained;
            ms_check = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_check).count();
            const bool failed = c.refined && (c.refined_explained - c.explained >= o.lost_min_gain ||
                                              c.explained < o.lost_explained_floor);
            failed_checks = failed ? failed_checks + 1 : 0;
            if (!failed) last_verified_t = r.t;
            if (c.refined)
                std::cout << "check at t " << std::fixed << std::setprecision(3) << r.t << ": explained "
                          << c.explained << ", " << c.refined_explained << " after aligning (moved " << c.moved_m
                          << " m, " << c.moved_deg << " deg): " << (failed ? "failed" : "passed") << std::endl;
        }
        if (o.kidnap_at_s >= 0 && !kidnapped && r.t >= f0.timestamp + o.kidnap_at_s)
        {
            kidnapped = true;
            Eigen::Isometry3d T_wrong = r.T_world_cam0;
            T_wrong.translation() += r.T_world_cam0.linear() * Eigen::Vector3d(o.kidnap_m, 0, 0);
            T_wrong.linear() = T_wrong.linear() * Eigen::AngleAxisd(o.kidnap_deg * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
            std::cout << "kidnapped at t " << std::fixed << std::setprecision(3) << r.t << ": restarted " << o.kidnap_m
                      << " m to the side, " << o.kidnap_deg << " deg turned" << std::endl;
            tracker.initialize(r.t, T_wrong, tracker.state().v_map, tracker.biasPrior(), nullptr);
        }
        bool restarted = false;
        if (search)
        {
            if ((r.lost || failed_checks >= 2) && !search->searching())
            {
                // Lost (lost_after_misses consecutive map alignments rejected, or the stereo geometry fits the map
                // better elsewhere): global localization looks for a start in the next frames, on its own thread,
                // while the tracker tracks on. A loss that was a false alarm (the view merely poorly explained)
                // then costs nothing.
                failed_checks = 0;
                ++losses;
                std::cout << "lost at t " << std::fixed << std::setprecision(3) << r.t << ": relocalizing" << std::endl;
                std::optional<tracking::SearchPrior> prior;
                if (o.relocalize_near_m > 0)
                    if (const auto known = log.poseAt(last_verified_t))
                        prior = tracking::SearchPrior{known->translation(), last_verified_t, o.relocalize_near_m,
                                                      o.relocalize_speed_m_s};
                starter->setBiasPrior(tracker.biasPrior());
                search->begin("reloc " + std::to_string(losses), prior, o.relocalize_single_fix);
            }
            if (search->searching())
            {
                // Only the hand-over counts in the frame's time: the search itself runs beside the tracker.
                const auto t_search = std::chrono::steady_clock::now();
                since_loss.emplace_back(f, tracker.state());
                search->push(f);
                const auto found = search->poll();
                ms_search = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_search).count();
                if (found) restarted = settle(*found, r.t);
            }
        }
        if (!restarted)  // else this frame is among those tracked again
        {
            log.addFrame(f, r, explained, ms_check, ms_search);
            if (n % 50 == 0)
                std::cout << "frame " << n << ": error " << std::fixed << std::setprecision(3) << log.lastErrorM()
                          << " m" << std::endl;
        }
        have_frame = (o.max_frames <= 0 || int(n) < o.max_frames) && nextFrame(f);
        if (!have_frame && search && search->searching())
        {
            // The frames ended with the search behind: let it finish them (a restart then tracks them again).
            if (const auto found = search->finish()) settle(*found, f.timestamp);
            have_frame = nextFrame(f);
        }
    }

    if (search && search->searching())
    {
        longest_unverified_s = std::max(longest_unverified_s, f.timestamp - last_verified_t);
        longest_wait_s = std::max(longest_wait_s, f.timestamp - last_verified_t);
        std::cout << "the frames ended during a relocalization search (unverified since t " << std::fixed
                  << std::setprecision(3) << last_verified_t << ")" << std::endl;
    }
    core::StagedOutputs out;
    core::writeTum(out.addFile(o.output_dir + "/trajectory.tum"), log.estimate());
    if (o.write_scene)
        app::writeTrackingScene(out.addFile(o.output_dir + "/scene.3Dscene"), map, log.groundTruth(), log.estimate());
    core::writeTextFileAtomically(out.addFile(o.output_dir + "/diagnostics.csv"), log.csv());
    if (starter) core::writeTextFileAtomically(out.addFile(o.output_dir + "/initialization.txt"), starter->record());
    auto sections = fo.sections();
    sections.insert(sections.end(), {{"Tracking", &o}, {"MapRefinement", &ro}, {"Estimator", &eo}, {"Reweighting", &rw},
                                     {"QuasiImage", &qo}});
    if (starter) sections.push_back({"GeometricLocalization", &go});
    core::writeEffectiveConfig(out.addFile(o.output_dir + "/quasiloc-track.ini"), sections,
                               "quasiloc-track effective configuration");
    out.commit();
    std::cout << log.summary(n, losses, withdrawn, relocalizations, longest_unverified_s, longest_wait_s)
              << "outputs     " << o.output_dir
              << "/{trajectory.tum,diagnostics.csv,quasiloc-track.ini" << (starter ? ",initialization.txt" : "")
              << (o.write_scene ? ",scene.3Dscene" : "") << "}" << std::endl;
    return 0;
}
}  // namespace

int main(int argc, char** argv) { return core::runProgram(argc, argv, kUsage, run); }
