// quasiloc-track: tracks a stereo + IMU rawlog against a LiDAR map (libs/tracking/tracker.h).
//
//     quasiloc-track <config.ini> [--set Section.key=value]... [--print-timing]
//
// [Tracking]: the tracker's keys (tracker.h) and
//   input_rawlog, calibration_ini (StereoRig keys + [imu] noise densities, as sim-rawlog writes), map_file,
//   groundtruth (TUM of T_world_cam0: initial state and the error table), output_dir, max_frames (0 = all),
//   write_scene (true: also scene.3Dscene).
// Other sections: [MapRefinement] [DirectAlignment] [Estimator] [Reweighting] [QuasiImage] and the front-end's.
// The initial state is given: the ground-truth pose of the first frame that has one, and the velocity from the
// ground truth of the first two frames (global-localization initialisation is not in this version).
//
// Outputs in output_dir, all or nothing: trajectory.tum (T_world_cam0), diagnostics.csv (one row per frame),
// quasiloc-track.ini (effective configuration), scene.3Dscene (map, ground truth in green, estimate in red: open with
// SceneViewer3D). Prints the error against ground truth and the time per frame.
#include <mrpt/config/CConfigFile.h>

#include <algorithm>
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
#include <quasiloc/dataset/frame_source.h>
#include <quasiloc/tracking/tracker.h>
#include <sstream>

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
    }
};

estimation::ImuNoise readImuNoise(const std::string& path)
{
    mrpt::config::CConfigFile cfg(path);
    estimation::ImuNoise n;
    core::require(cfg.sectionExists("imu"), path, "no [imu] section (IMU noise densities)");
    n.gyro_noise_density = core::readIniDouble(cfg, "imu", "gyroscope_noise_density", n.gyro_noise_density);
    n.acc_noise_density = core::readIniDouble(cfg, "imu", "accelerometer_noise_density", n.acc_noise_density);
    n.gyro_random_walk = core::readIniDouble(cfg, "imu", "gyroscope_random_walk", n.gyro_random_walk);
    n.acc_random_walk = core::readIniDouble(cfg, "imu", "accelerometer_random_walk", n.acc_random_walk);
    n.gravity_m_s2 = core::readIniDouble(cfg, "imu", "gravity_m_s2", n.gravity_m_s2);
    return n;
}

double percentile(std::vector<double> v, double p)
{
    if (v.empty()) return NAN;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(p / 100.0 * double(v.size())))];
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
    tracking::Tracker tracker(o, ro, eo, rw, source->rig(), readImuNoise(o.calibration_ini), renderer, frontend);
    std::cout << "map " << map.summary() << "\n" << source->description() << std::endl;

    // The first two frames with ground truth give the initial pose and velocity.
    dataset::StereoFrame f0, f;
    while (source->next(f0) && !f0.T_world_cam0) {}
    core::require(bool(f0.T_world_cam0), o.input_rawlog, "no frame with a ground-truth pose");
    core::require(source->next(f) && f.T_world_cam0, o.input_rawlog, "the second frame has no ground-truth pose");
    const Eigen::Isometry3d T_body_cam = core::toIsometry(source->rig().T_body_left);
    const Eigen::Vector3d p0 = (core::toIsometry(*f0.T_world_cam0) * T_body_cam.inverse()).translation();
    const Eigen::Vector3d p1 = (core::toIsometry(*f.T_world_cam0) * T_body_cam.inverse()).translation();
    tracker.initialize(f0.timestamp, core::toIsometry(*f0.T_world_cam0), (p1 - p0) / (f.timestamp - f0.timestamp), &f0);

    core::Trajectory traj;
    traj.header = "quasiloc-track estimate: T_world_cam0 (the left camera in the map frame)";
    traj.poses.push_back({f0.timestamp, *f0.T_world_cam0});
    core::Trajectory gt_traj;  // the ground truth at the tracked frames (for the .3Dscene)
    gt_traj.poses.push_back({f0.timestamp, *f0.T_world_cam0});
    std::ostringstream csv;
    csv << "t,keyframe,map_update,correction_m,correction_deg,edge_inlier_ratio,edge_points,prior_sigma_m,"
           "prior_sigma_deg,lost,landmarks,error_m,error_deg,ms_predict,ms_image,ms_align,ms_visual,ms_window,ms_total,"
           "bg_x,bg_y,bg_z,ba_x,ba_y,ba_z\n";
    std::vector<double> err_m, ms;
    int updates = 0, keyframes = 0, lost_frames = 0;
    size_t n = 1;
    do
    {
        const tracking::FrameReport r = tracker.track(f);
        traj.poses.push_back({r.t, core::fromIsometry(r.T_world_cam0)});
        double e_m = NAN, e_deg = NAN;
        if (f.T_world_cam0)
        {
            const Eigen::Isometry3d G = core::toIsometry(*f.T_world_cam0);
            e_m = (r.T_world_cam0.translation() - G.translation()).norm();
            e_deg = Eigen::AngleAxisd(r.T_world_cam0.linear().transpose() * G.linear()).angle() * 180 / M_PI;
            err_m.push_back(e_m);
            gt_traj.poses.push_back({r.t, *f.T_world_cam0});
        }
        ms.push_back(r.ms_total);
        updates += r.map_update, keyframes += r.keyframe, lost_frames += r.lost;
        csv << std::setprecision(17) << r.t << std::setprecision(6) << "," << r.keyframe << "," << r.map_update << ","
            << r.correction_m << "," << r.correction_deg << "," << r.edge_inlier_ratio << "," << r.edge_points << ","
            << r.prior_sigma_m << "," << r.prior_sigma_deg << "," << r.lost << "," << r.landmarks << "," << e_m << ","
            << e_deg << "," << r.ms_predict << "," << r.ms_image << "," << r.ms_align << "," << r.ms_visual << ","
            << r.ms_window << "," << r.ms_total << "," << r.gyro_bias.x() << "," << r.gyro_bias.y() << ","
            << r.gyro_bias.z() << "," << r.acc_bias.x() << "," << r.acc_bias.y() << "," << r.acc_bias.z() << "\n";
        if (++n % 50 == 0) std::cout << "frame " << n << ": error " << std::fixed << std::setprecision(3) << e_m << " m" << std::endl;
    } while ((o.max_frames <= 0 || int(n) < o.max_frames) && source->next(f));

    core::StagedOutputs out;
    core::writeTum(out.addFile(o.output_dir + "/trajectory.tum"), traj);
    if (o.write_scene) app::writeTrackingScene(out.addFile(o.output_dir + "/scene.3Dscene"), map, gt_traj, traj);
    core::writeTextFileAtomically(out.addFile(o.output_dir + "/diagnostics.csv"), csv.str());
    auto sections = fo.sections();
    sections.insert(sections.end(), {{"Tracking", &o}, {"MapRefinement", &ro}, {"Estimator", &eo}, {"Reweighting", &rw},
                                     {"QuasiImage", &qo}});
    core::writeEffectiveConfig(out.addFile(o.output_dir + "/quasiloc-track.ini"), sections,
                               "quasiloc-track effective configuration");
    out.commit();

    double sq = 0;
    for (double e : err_m) sq += e * e;
    std::cout << std::fixed << std::setprecision(3) << "frames      " << n << " (keyframes " << keyframes
              << ", map updates accepted " << updates << ", frames marked lost " << lost_frames << ")\n"
              << "ATE         RMSE " << 100 * std::sqrt(sq / double(std::max<size_t>(1, err_m.size()))) << " cm, median "
              << 100 * percentile(err_m, 50) << " cm, max " << 100 * percentile(err_m, 100)
              << " cm (map frame, no alignment, vs ground truth at " << err_m.size() << " frames)\n"
              << "time/frame  median " << percentile(ms, 50) << " ms, p90 " << percentile(ms, 90) << " ms, max "
              << percentile(ms, 100) << " ms\n"
              << "outputs     " << o.output_dir << "/{trajectory.tum,diagnostics.csv,quasiloc-track.ini"
              << (o.write_scene ? ",scene.3Dscene" : "") << "}" << std::endl;
    return 0;
}
}  // namespace

int main(int argc, char** argv) { return core::runProgram(argc, argv, kUsage, run); }
