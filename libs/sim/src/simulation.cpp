#include <mrpt/system/CTimeLogger.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <opencv2/imgcodecs.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/dataset/rawlog_writer.h>
#include <quasiloc/sim/inspection.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/dataset/calibration.h>
#include <quasiloc/dataset/kalibr.h>
#include <quasiloc/sim/floor_world.h>
#include <quasiloc/sim/lidar_sweeps.h>
#include <quasiloc/sim/material_labels.h>
#include <quasiloc/sim/simulation.h>
#include <quasiloc/sim/trajectory_spline.h>
#include <sstream>

namespace quasiloc::sim
{
namespace fs = std::filesystem;

namespace
{
double seconds(std::chrono::steady_clock::time_point a)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
}

/** The IMU samples of the sequence with their rawlog timestamps and, when synthesized, the true biases. */
struct SimulatedImu
{
    std::vector<int64_t> t_ns;  ///< rawlog timestamps, parallel to samples
    std::vector<dataset::ImuSample> samples;
    std::vector<ImuTruth> truth;  ///< empty for source = real (biases unknown)
    std::string description;      ///< source and bias model, one line
};

/** source = real also moves the frame times onto the real IMU's ticks (snapToImuTicks). */
SimulatedImu simulateImu(const SimulationOptions& so, const ImuNoiseOptions& io, const TrajectorySpline& spline,
                         std::vector<int64_t>& frame_ns, const std::string& config_name)
{
    SimulatedImu out;
    if (io.source == ImuSource::real)
    {
        const std::string path = io.real_imu_csv.empty()
                                     ? so.shared_dir + "/data/euroc/V1_01_easy_micro/mav0/imu0/data.csv"
                                     : io.real_imu_csv;
        const dataset::EurocImuCsv all = dataset::readEurocImuCsv(path, io.rate_hz);
        const size_t snapped = snapToImuTicks(frame_ns, all.t_ns);
        dataset::EurocImuCsv real = selectRealImu(all, frame_ns.front(), frame_ns.back(), io.rate_hz);
        out.t_ns = std::move(real.t_ns);
        out.samples = std::move(real.samples);
        out.description = "real samples of " + path + " replayed on the ground-truth clock (source = real; " +
                          std::to_string(snapped) + " of " + std::to_string(frame_ns.size()) +
                          " frame times moved <= 1 us onto its ticks); true biases unknown, no gt_imu_bias.csv";
        return out;
    }
    const double t0 = frame_ns.front() * 1e-9, t1 = frame_ns.back() * 1e-9;
    ImuNoiseOptions imu_opt = io;
    imu_opt.seed = io.seed * 0x9E3779B97F4A7C15ull + so.seed;
    if (io.bias == ImuBiasModel::random_draw) drawInitialBiases(imu_opt);
    ResolvedImuBias bias = resolveImuBias(imu_opt, so.shared_dir, so.sequence, t0, t1, config_name);
    ImuSynthesizer synth(spline, imu_opt, std::move(bias.trajectory));
    out.samples = synth.generate(t0, t1, &out.truth);
    // Integer ticks from the first frame: every (rate / camera rate)-th sample has exactly a frame's timestamp,
    // as in EuRoC (rounding s.t, ~1.4e9 s in a double, would scatter them by +-120 ns around the frames).
    for (size_t k = 0; k < out.samples.size(); ++k)
        out.t_ns.push_back(frame_ns.front() +
                           static_cast<int64_t>(std::llround(static_cast<double>(k) * 1e9 / io.rate_hz)));
    out.description =
        std::string("synthetic") + (io.noise_enabled ? "" : " (noiseless)") + ", biases: " + bias.description;
    return out;
}

/** gt_imu_bias.csv: the true biases added to every IMU sample of the rawlog. */
std::string imuBiasCsv(const SimulatedImu& imu, const std::string& sequence)
{
    std::string text = "# True IMU biases of every IMU sample of " + sequence +
                       ".rawlog (body = IMU frame): " + imu.description +
                       "\n# t [s], b_g_x, b_g_y, b_g_z [rad/s], b_a_x, b_a_y, b_a_z [m/s^2]\n";
    char line[200];
    for (size_t i = 0; i < imu.truth.size(); ++i)
    {
        const ImuTruth& b = imu.truth[i];
        std::snprintf(line, sizeof(line), "%.9f,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", imu.t_ns[i] * 1e-9, b.gyro_bias.x(),
                      b.gyro_bias.y(), b.gyro_bias.z(), b.acc_bias.x(), b.acc_bias.y(), b.acc_bias.z());
        text += line;
    }
    return text;
}

std::string readme(const SimulationOptions& o, const WorldOptions& wo, const LidarOptions& lo,
                   const SimulationResult& r, bool beam, const core::StereoRig& rig)
{
    std::ostringstream s;
    if (o.motion == MotionSource::car)
        s << "Simulated car sequence written by sim-rawlog (quasiloc sim library).\n\n"
          << "World: an outdoor campus of streets and blocks (campus_world.h), motion: a car's route along its\n"
          << "streets (car_motion.h), seed " << o.seed << ".\n";
    else if (o.motion == MotionSource::ground_robot)
        s << "Simulated ground-robot sequence written by sim-rawlog (quasiloc sim library).\n\n"
          << "World: an office floor of rooms along a corridor (floor_world.h), motion: a ground robot's tour of it\n"
          << "(robot_motion.h), " << (o.robot.start_moving ? "started moving" : "started standing") << ", seed "
          << o.seed << ".\n";
    else
        s << "Simulated EuRoC-like sequence written by sim-rawlog (quasiloc sim library).\n\n"
          << "World: EuRoC Vicon room " << roomName(wo.world)
          << " (shell and clutter from the GMMLoc GMM and line maps, plus\n"
          << "procedural objects), trajectory: "
          << (o.trajectory.empty() ? "EuRoC ground truth of " + o.sequence : o.trajectory) << ", seed " << o.seed
          << ".\n";
    s << r.frames << " stereo frames at " << o.camera_rate_hz << " Hz, " << r.imu_samples
      << " IMU samples.\nIMU: " << r.imu_description << ".\nMap: " << r.map_points
      << " points. Minimum clearance between the room's trajectories\n"
      << "and the geometry: " << r.world.min_clearance_m << " m.\n\nFiles:\n"
      << (lo.map_source == MapSource::sweeps
              ? "  lidar_map.map        LiDAR map built by map-build from simulated sweeps of a mapping run "
                "(lidar_sweeps.h):\n                       MRPT CPointsMapXYZI (map::LidarMap), intensity = "
                "reflectivity [0,1]\n"
              : "  lidar_map.map        survey LiDAR map: MRPT CPointsMapXYZI (map::LidarMap), intensity = "
                "reflectivity [0,1]\n")
      << (beam ? "  lidar_map_32beam.map sparse 32-beam-like variant of the map\n" : "")
      << (o.write_map && o.write_map_materials
              ? "  lidar_map_materials.bin the material of every map point (sim/material_labels.h)\n"
              : "")
      << "  " << o.sequence
      << ".rawlog   MRPT rawlog: CObservationStereoImages 'stereo' + CObservationIMU 'imu', time order\n"
      << "  " << o.sequence << "_Images/  raw (distorted) " << rig.left.width << "x" << rig.left.height
      << " 8-bit PNG images referenced by the rawlog\n"
      << "  gt.tum               ground truth T_world_cam0 (TUM: t x y z qx qy qz qw) at every camera frame\n"
      << "  gt_body.tum          ground truth T_world_body (IMU frame) at every IMU sample\n"
      << (r.imu_bias_written ? "  gt_imu_bias.csv      true IMU biases at every IMU sample (t, b_g xyz, b_a xyz)\n"
                             : "")
      << "  calib.ini            stereo rig (sections camera_left, camera_right, camera_rig) and [imu] noise model\n"
      << "  sim-rawlog.ini       the effective configuration (re-run sim-rawlog with it to reproduce the folder)\n"
      << "  inspection.png       camera frame | LiDAR reflectivity projected at the same pose | edges overlay\n\n"
      << "The camera sees albedo x lighting; the LiDAR reflectivity is a different material response with its own\n"
      << "detail, range and incidence falloff and noise: the two are correlated, not equal.\n";
    return s.str();
}
/** The rig: a Kalibr camchain, or the two EuRoC sensor.yaml files (EuRoC's own by default). */
core::StereoRig loadRig(const SimulationOptions& so)
{
    if (!so.camchain.empty()) return dataset::stereoRigFromKalibr(so.camchain);
    const std::string calib_dir = so.shared_dir + "/data/euroc/calib/";
    return core::StereoRig::fromEuroc(so.cam0_yaml.empty() ? calib_dir + "cam0_sensor.yaml" : so.cam0_yaml,
                                      so.cam1_yaml.empty() ? calib_dir + "cam1_sensor.yaml" : so.cam1_yaml);
}

/** The body (IMU) trajectory and where the frames start: a fitted trajectory file, or the ground robot's tour. */
struct SimulatedMotion
{
    TrajectorySpline spline;
    double first_frame_offset_s = 0;  ///< after spline.tStart()
    std::string source;               ///< the trajectory file, or the robot's tour in words
    std::optional<FloorLayout> floor;
    std::optional<CampusLayout> campus;
    std::vector<Eigen::Vector3f> path_cam0;  ///< robot only: cam0 positions along the whole tour (5 cm apart or less)
};

/** The robot's clock starts at a realistic UNIX time, as a real recording's would. */
constexpr double kRobotClockStart_s = 1.7e9;

SimulatedMotion robotMotion(const SimulationOptions& so, const WorldOptions& wo, const core::StereoRig& rig,
                            const std::string& config_name)
{
    core::require(wo.world == ViconRoom::office_floor, config_name + " [World] world",
                  "must be floor with [Simulation] motion = ground_robot");
    SimulatedMotion m;
    m.floor = makeFloorLayout(wo.floor, so.seed, config_name + " [World]");
    const double duration = so.duration_s > 0 ? so.duration_s + so.start_offset_s : 60.0;
    const GroundRobotMotion robot = generateGroundRobotMotion(*m.floor, so.robot, duration, kRobotClockStart_s, so.seed,
                                                              config_name + " [Simulation]");
    const mrpt::poses::CPose3D T_base_cam0 = baseToCamera(so.robot);
    const mrpt::poses::CPose3D T_cam0_body = core::fromIsometry(core::toIsometry(rig.T_body_left).inverse());
    core::Trajectory body;
    body.header = "T_world_body of the ground robot";
    for (const core::TimedPose& tp : robot.T_world_base.poses)
    {
        const mrpt::poses::CPose3D T_world_cam0 = tp.pose + T_base_cam0;
        body.poses.push_back({tp.t, T_world_cam0 + T_cam0_body});
        const Eigen::Vector3f p(float(T_world_cam0.x()), float(T_world_cam0.y()), float(T_world_cam0.z()));
        if (m.path_cam0.empty() || (m.path_cam0.back() - p).norm() > 0.05f) m.path_cam0.push_back(p);
    }
    TrajectorySplineOptions spo;
    spo.knot_spacing_s = so.spline_knot_spacing_s;
    m.spline = TrajectorySpline::fitBodyTrajectory(body, spo);
    m.first_frame_offset_s = robot.first_frame_offset_s + so.start_offset_s;
    char text[200];
    std::snprintf(text, sizeof(text),
                  "ground robot tour: %zu waypoints, %.1f m, %zu rooms entered, %zu turns in "
                  "place, %zu waits",
                  robot.waypoints.size(), robot.length_m, robot.rooms_visited, robot.turns_in_place, robot.stops);
    m.source = text;
    return m;
}

SimulatedMotion carMotion(const SimulationOptions& so, const WorldOptions& wo, const core::StereoRig& rig,
                          const std::string& config_name)
{
    core::require(wo.world == ViconRoom::campus, config_name + " [World] world",
                  "must be campus with [Simulation] motion = car");
    SimulatedMotion m;
    m.campus = makeCampusLayout(wo.campus, config_name + " [World]");
    const CarMotion car = driveCarRoute(*m.campus, planCarRoute(*m.campus, so.car, so.seed), so.car, kRobotClockStart_s,
                                        so.seed, config_name + " [Simulation]");
    const mrpt::poses::CPose3D T_base_cam0 = carBaseToCamera(so.car);
    const mrpt::poses::CPose3D T_cam0_body = core::fromIsometry(core::toIsometry(rig.T_body_left).inverse());
    core::Trajectory body;
    body.header = "T_world_body of the car";
    for (const core::TimedPose& tp : car.T_world_base.poses)
    {
        const mrpt::poses::CPose3D T_world_cam0 = tp.pose + T_base_cam0;
        body.poses.push_back({tp.t, T_world_cam0 + T_cam0_body});
        const Eigen::Vector3f p(float(T_world_cam0.x()), float(T_world_cam0.y()), float(T_world_cam0.z()));
        if (m.path_cam0.empty() || (m.path_cam0.back() - p).norm() > 0.25f) m.path_cam0.push_back(p);
    }
    TrajectorySplineOptions spo;
    spo.knot_spacing_s = so.spline_knot_spacing_s;
    m.spline = TrajectorySpline::fitBodyTrajectory(body, spo);
    m.first_frame_offset_s = car.first_frame_offset_s + so.start_offset_s;
    char text[200];
    std::snprintf(text, sizeof(text),
                  "car route: %zu intersections, %.1f m in %.1f s, top speed %.1f m/s, %zu turns, %zu stops",
                  car.intersections.size(), car.length_m, car.duration_s, car.top_speed_m_s, car.turns, car.stops);
    m.source = text;
    return m;
}

SimulatedMotion trajectoryMotion(const SimulationOptions& so, const core::StereoRig& rig)
{
    SimulatedMotion m;
    m.source =
        so.trajectory.empty() ? so.shared_dir + "/data/euroc/groundtruth/cam0/" + so.sequence + ".txt" : so.trajectory;
    const core::Trajectory traj = core::readTum(m.source);
    TrajectorySplineOptions spo;
    spo.knot_spacing_s = so.spline_knot_spacing_s;
    m.spline = TrajectorySpline::fitCameraTrajectory(traj, rig.T_body_left, spo);
    m.first_frame_offset_s = so.start_offset_s;
    return m;
}
}  // namespace

SimulationResult runSimulation(const mrpt::config::CConfigFileBase& cfg, const std::string& config_name,
                               bool print_timing)
{
    const auto t_total = std::chrono::steady_clock::now();
    mrpt::system::CTimeLogger timer(print_timing, "sim-rawlog");
    SimulationOptions so;
    WorldOptions wo;
    AppearanceOptions ao;
    LidarOptions lo;
    ImuNoiseOptions io;
    core::loadOptionsChecked(so, cfg, "Simulation", config_name);
    core::loadOptionsChecked(wo, cfg, "World", config_name);
    core::loadOptionsChecked(ao, cfg, "Appearance", config_name);
    core::loadOptionsChecked(lo, cfg, "Lidar", config_name);
    core::loadOptionsChecked(io, cfg, "IMU", config_name);
    so.check(config_name + " [Simulation]");
    wo.check(config_name + " [World]");
    ao.check(config_name + " [Appearance]");
    lo.check(config_name + " [Lidar]");
    io.check(config_name + " [IMU]");
    if (!io.kalibr_yaml.empty())
    {
        const dataset::ImuCalibration c = dataset::imuCalibrationFromKalibr(io.kalibr_yaml);
        io.rate_hz = c.rate_hz;
        io.gyroscope_noise_density = c.gyroscope_noise_density;
        io.gyroscope_random_walk = c.gyroscope_random_walk;
        io.accelerometer_noise_density = c.accelerometer_noise_density;
        io.accelerometer_random_walk = c.accelerometer_random_walk;
        io.check(io.kalibr_yaml);
    }
    auto log = [&](const std::string& msg) {
        if (so.verbose) std::cout << msg << std::endl;
    };

    // Inputs: calibration, trajectory, spline.
    const core::StereoRig rig = loadRig(so);
    const bool robot = so.motion == MotionSource::ground_robot, car = so.motion == MotionSource::car;
    core::require(robot || wo.world != ViconRoom::office_floor, config_name + " [World] world",
                  "floor needs [Simulation] motion = ground_robot");
    core::require(car || wo.world != ViconRoom::campus, config_name + " [World] world",
                  "campus needs [Simulation] motion = car");
    const SimulatedMotion motion = robot ? robotMotion(so, wo, rig, config_name)
                                   : car ? carMotion(so, wo, rig, config_name)
                                         : trajectoryMotion(so, rig);
    const std::string& traj_path = motion.source;
    const TrajectorySpline& spline = motion.spline;
    if (robot || car) log(motion.source);
    const mrpt::poses::CPose3D T_body_cam0 = rig.T_body_left;
    auto T_world_cam0 = [&](double t) { return spline.T_world_body(t) + T_body_cam0; };

    const auto t0_ns = static_cast<int64_t>(std::llround((spline.tStart() + motion.first_frame_offset_s) * 1e9));
    const auto end_ns = static_cast<int64_t>(std::floor(spline.tEnd() * 1e9));
    const int64_t last_ns =
        so.duration_s > 0 ? std::min(end_ns, t0_ns + static_cast<int64_t>(so.duration_s * 1e9)) : end_ns;
    const double period_ns = 1e9 / so.camera_rate_hz;
    std::vector<int64_t> frame_ns;
    for (int64_t k = 0;; ++k)
    {
        const auto t = t0_ns + static_cast<int64_t>(std::llround(k * period_ns));
        if (t > last_ns) break;
        frame_ns.push_back(t);
    }
    core::require(!frame_ns.empty(), config_name + " [Simulation] start_offset_s",
                  "leaves no camera frame inside the trajectory " + traj_path);

    // IMU on [first frame, last frame], before the slow stages so that a bad IMU input fails early.
    SimulationResult r;
    timer.enter("imu");
    const SimulatedImu imu = simulateImu(so, io, spline, frame_ns, config_name);
    timer.leave("imu");
    r.imu_description = imu.description;
    log("IMU: " + imu.description);

    // World: clear of every trajectory of the room and of the simulated one.
    auto clock = std::chrono::steady_clock::now();
    std::vector<Eigen::Vector3f> keep_clear =
        robot || car ? motion.path_cam0 : loadRoomTrajectoryPositions(so.shared_dir, roomName(wo.world));
    for (int64_t t : frame_ns)
    {
        const mrpt::poses::CPose3D T = T_world_cam0(t * 1e-9);
        keep_clear.emplace_back(static_cast<float>(T.x()), static_cast<float>(T.y()), static_cast<float>(T.z()));
    }
    timer.enter("world");
    const World world = robot ? buildFloorWorld(wo, *motion.floor, so.seed, keep_clear, &r.world)
                        : car ? buildCampusWorld(wo, *motion.campus, so.seed, keep_clear, &r.world)
                              : buildWorld(wo, so.shared_dir, so.seed, keep_clear, &r.world);
    timer.leave("world");
    r.world_time_s = seconds(clock);
    log("world " + roomName(wo.world) + ": " + std::to_string(r.world.triangles) + " triangles, " +
        std::to_string(r.world.gmm_patches) + " GMM patches, " + std::to_string(r.world.objects_placed) +
        " objects, min clearance " + std::to_string(r.world.min_clearance_m) + " m (" + std::to_string(r.world_time_s) +
        " s)");

    core::StagedOutputs staged;
    const fs::path out_final(so.output_dir);
    const fs::path dir(staged.addFolder(so.output_dir));

    // LiDAR map(s).
    clock = std::chrono::steady_clock::now();
    map::LidarMap lidar_map;
    LidarStats ls;
    LidarPointInfo point_info;
    const bool swept = lo.map_source == MapSource::sweeps;
    core::require(!(swept && so.write_map_materials), config_name + " [Simulation] write_map_materials",
                  "is for the exact map only ([Lidar] map_source = exact): a swept map's points are voxel means");
    std::string map_summary;
    if ((so.write_map || so.inspection_png) && swept)
    {
        timer.enter("lidar map (sweeps)");
        std::vector<Eigen::Vector3f> waypoints;
        if (robot)  // a tour of the floor, at least two minutes of the robot's driving long
            for (const Eigen::Vector2d& w : planFloorTour(*motion.floor, so.robot, 120.0, so.seed ^ 0x3A9ull))
                waypoints.emplace_back(float(w.x()), float(w.y()), 0.f);
        if (car) waypoints = campusMappingTour(*motion.campus);  // every street, as a mapping car drives them
        const SweptMap swept_map = buildSweptMap(world, waypoints, lo, so.seed, (out_final / "lidar_map.map").string());
        timer.leave("lidar map (sweeps)");
        lidar_map = swept_map.build.map;
        map_summary = swept_map.summary();
    }
    else if (so.write_map || so.inspection_png)
    {
        timer.enter("lidar map");
        lidar_map = sampleSurveyMap(world, lo, so.seed, &ls, so.write_map_materials ? &point_info : nullptr);
        timer.leave("lidar map");
    }
    if (so.write_map)
    {
        lidar_map.save((dir / "lidar_map.map").string());
        r.files.push_back((out_final / "lidar_map.map").string());
        if (so.write_map_materials)
        {
            saveMaterialLabels((dir / kMaterialLabelsFile).string(), point_info.material);
            r.files.push_back((out_final / kMaterialLabelsFile).string());
        }
        if (lo.beam_map)
        {
            const map::LidarMap beam = sampleBeamMap(world, lo, so.seed);
            beam.save((dir / "lidar_map_32beam.map").string());
            r.beam_map_points = beam.size();
            r.files.push_back((out_final / "lidar_map_32beam.map").string());
        }
    }
    r.map_points = lidar_map.size();
    r.map_time_s = seconds(clock);
    if (swept)
        log("LiDAR map: " + map_summary + " (" + std::to_string(r.map_time_s) + " s in all)");
    else
        log("LiDAR map: " + std::to_string(r.map_points) + " points of " + std::to_string(ls.sampled) + " sampled (" +
            std::to_string(ls.not_visible) + " not seen by any of " + std::to_string(ls.stations.size()) +
            " stations), " + std::to_string(r.map_time_s) + " s");

    // Rawlog: IMU samples interleaved in time order with the rendered stereo frames.
    const std::string rawlog_path = (dir / (so.sequence + ".rawlog")).string();
    dataset::RawlogWriter writer(rawlog_path, rig);
    StereoRenderer renderer(world, rig, ao, so.seed);
    core::Trajectory gt_cam, gt_body;
    gt_cam.header = "T_world_cam0 of the simulated sequence " + so.sequence;
    gt_body.header = "T_world_body (IMU frame) of the simulated sequence " + so.sequence;
    size_t k_imu = 0;
    cv::Mat inspect_left;
    const size_t inspect_frame = frame_ns.size() / 2;
    double render_total = 0;
    for (size_t f = 0; f < frame_ns.size(); ++f)
    {
        // Episodes (illumination, occluder) are tied to the trajectory's clock, not to start_offset_s.
        const double t = frame_ns[f] * 1e-9, t_rel = t - spline.tStart();
        for (; k_imu < imu.samples.size() && imu.t_ns[k_imu] <= frame_ns[f]; ++k_imu)
        {
            writer.writeImuNs(imu.t_ns[k_imu], imu.samples[k_imu]);
            gt_body.poses.push_back({imu.samples[k_imu].t, spline.T_world_body(imu.samples[k_imu].t)});
        }
        std::vector<mrpt::poses::CPose3D> poses;
        const int n_blur = ao.motion_blur_samples;
        for (int b = 0; b < n_blur; ++b)
        {
            const double dt =
                n_blur > 1 ? (static_cast<double>(b) / (n_blur - 1) - 0.5) * ao.exposure_time_ms * 1e-3 : 0.0;
            poses.push_back(T_world_cam0(std::clamp(t + dt, spline.tStart(), spline.tEnd())));
        }
        cv::Mat left, right;
        const auto c = std::chrono::steady_clock::now();
        timer.enter("render stereo frame");
        renderer.render(poses, t_rel, f, left, right);
        timer.leave("render stereo frame");
        const double ms = seconds(c) * 1e3;
        render_total += ms;
        r.max_render_ms = std::max(r.max_render_ms, ms);
        writer.writeStereoNs(frame_ns[f], left, right);
        gt_cam.poses.push_back({t, T_world_cam0(t)});
        if (f == inspect_frame) inspect_left = left;
        if (so.verbose && (f % 100 == 0 || f + 1 == frame_ns.size()))
            std::cout << "frame " << f + 1 << "/" << frame_ns.size() << " (" << ms << " ms)" << std::endl;
    }
    for (; k_imu < imu.samples.size(); ++k_imu)
    {
        writer.writeImuNs(imu.t_ns[k_imu], imu.samples[k_imu]);
        gt_body.poses.push_back({imu.samples[k_imu].t, spline.T_world_body(imu.samples[k_imu].t)});
    }
    writer.close();
    r.frames = writer.numStereo();
    r.imu_samples = writer.numImu();
    r.render_time_s = render_total * 1e-3;
    r.mean_render_ms = render_total / static_cast<double>(frame_ns.size());
    r.files.push_back((out_final / (so.sequence + ".rawlog")).string());
    r.files.push_back((out_final / (so.sequence + "_Images")).string() + "/");

    core::writeTum((dir / "gt.tum").string(), gt_cam);
    core::writeTum((dir / "gt_body.tum").string(), gt_body);
    if (!imu.truth.empty())
    {
        core::writeTextFileAtomically((dir / "gt_imu_bias.csv").string(), imuBiasCsv(imu, so.sequence));
        r.imu_bias_written = true;
        r.files.push_back((out_final / "gt_imu_bias.csv").string());
    }
    // The calibration a user would have: the rig and the IMU's noise model, not the biases the simulation drew.
    dataset::SensorCalibration calib;
    calib.rig = rig;
    calib.imu = dataset::ImuCalibration{};
    calib.imu->rate_hz = io.rate_hz;
    calib.imu->gyroscope_noise_density = io.gyroscope_noise_density;
    calib.imu->gyroscope_random_walk = io.gyroscope_random_walk;
    calib.imu->accelerometer_noise_density = io.accelerometer_noise_density;
    calib.imu->accelerometer_random_walk = io.accelerometer_random_walk;
    calib.imu->gravity_m_s2 = io.gravity_m_s2;
    dataset::saveCalibration(calib, (dir / "calib.ini").string(),
                             std::string(so.camchain.empty() ? "Simulated EuRoC" : "Simulated (" + so.camchain + ")") +
                                 " stereo rig (cam0 = left, cam1 = right; body = IMU frame) and IMU noise "
                                 "model;\nthe biases were not measured (zero, with the sigmas of real MEMS biases)");
    core::writeEffectiveConfig((dir / "sim-rawlog.ini").string(),
                               {{"Simulation", &so}, {"World", &wo}, {"Appearance", &ao}, {"Lidar", &lo}, {"IMU", &io}},
                               "Effective configuration of sim-rawlog (" + config_name + ")");
    for (const char* f : {"gt.tum", "gt_body.tum", "calib.ini", "sim-rawlog.ini"})
        r.files.push_back((out_final / f).string());
    if (so.inspection_png && !inspect_left.empty())
    {
        const cv::Mat refl = projectReflectivity(lidar_map, rig.left, gt_cam.poses[inspect_frame].pose);
        core::require(cv::imwrite((dir / "inspection.png").string(), makeInspectionImage(inspect_left, refl)),
                      (out_final / "inspection.png").string(), "cannot write PNG");
        r.files.push_back((out_final / "inspection.png").string());
    }
    r.total_time_s = seconds(t_total);
    core::writeTextFileAtomically((dir / "README.txt").string(),
                                  readme(so, wo, lo, r, lo.beam_map && so.write_map, rig));
    r.files.push_back((out_final / "README.txt").string());
    staged.commit();
    return r;
}

}  // namespace quasiloc::sim
