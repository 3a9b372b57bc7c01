#include "run_log.h"

#include <quasiloc/core/pose.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace quasiloc::app
{
namespace
{
double percentile(std::vector<double> v, double p)
{
    if (v.empty()) return NAN;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(p / 100.0 * double(v.size())))];
}
}  // namespace

const char* const kCsvHeader =
    "t,keyframe,map_update,correction_m,correction_deg,edge_inlier_ratio,edge_points,prior_sigma_m,"
    "prior_sigma_deg,lost,landmarks,error_m,error_deg,ms_predict,ms_image,ms_align,ms_visual,ms_window,ms_total,"
    "bg_x,bg_y,bg_z,ba_x,ba_y,ba_z,stereo_map_points,explained_ratio,ms_check,camera_lines,map_lines,line_factors,"
    "line_candidates,line_window_px,ms_lines,ms_search,quasi_keypoints,point_factors,ms_points,plane_factors,plane_candidates,ms_planes,"
    "bg_sigma_x,bg_sigma_y,bg_sigma_z,ba_sigma_x,ba_sigma_y,ba_sigma_z,standing\n";

RunLog::RunLog() { traj_.header = "quasiloc-track estimate: T_world_cam0 (the left camera in the map frame)"; }

void RunLog::addStart(const dataset::StereoFrame& frame, const Eigen::Isometry3d& T_world_cam0)
{
    traj_.poses.push_back({frame.timestamp, core::fromIsometry(T_world_cam0)});
    if (frame.T_world_cam0) gt_traj_.poses.push_back({frame.timestamp, *frame.T_world_cam0});
}

void RunLog::addFrame(const dataset::StereoFrame& f, const tracking::FrameReport& r, double explained_ratio,
                      double ms_check, double ms_search)
{
    traj_.poses.push_back({r.t, core::fromIsometry(r.T_world_cam0)});
    double e_deg = NAN;
    Row row;
    row.t = r.t;
    if (f.T_world_cam0)
    {
        const Eigen::Isometry3d G = core::toIsometry(*f.T_world_cam0);
        row.error_m = core::translationDistance(r.T_world_cam0, G);
        e_deg = core::rotationDistanceRad(r.T_world_cam0, G) * 180 / M_PI;
        gt_traj_.poses.push_back({r.t, *f.T_world_cam0});
    }
    row.ms = r.ms_total + ms_check + ms_search;
    row.map_update = r.map_update, row.keyframe = r.keyframe, row.lost = r.lost;
    std::ostringstream csv;
    csv << std::setprecision(17) << r.t << std::setprecision(6) << "," << r.keyframe << "," << r.map_update << ","
        << r.correction_m << "," << r.correction_deg << "," << r.edge_inlier_ratio << "," << r.edge_points << ","
        << r.prior_sigma_m << "," << r.prior_sigma_deg << "," << r.lost << "," << r.landmarks << "," << row.error_m
        << "," << e_deg << "," << r.ms_predict << "," << r.ms_image << "," << r.ms_align << "," << r.ms_visual << ","
        << r.ms_window << "," << r.ms_total << "," << r.gyro_bias.x() << "," << r.gyro_bias.y() << ","
        << r.gyro_bias.z() << "," << r.acc_bias.x() << "," << r.acc_bias.y() << "," << r.acc_bias.z() << ","
        << r.stereo_map_points << "," << explained_ratio << "," << ms_check << "," << r.camera_lines << ","
        << r.map_lines << "," << r.line_factors << "," << r.line_candidates << "," << r.line_window_px << ","
        << r.ms_lines << "," << ms_search << "," << r.quasi_keypoints << "," << r.point_factors << "," << r.ms_points
        << "," << r.plane_factors << "," << r.plane_candidates << "," << r.ms_planes << "," << r.gyro_bias_sigma.x()
        << "," << r.gyro_bias_sigma.y() << "," << r.gyro_bias_sigma.z() << "," << r.acc_bias_sigma.x() << ","
        << r.acc_bias_sigma.y() << "," << r.acc_bias_sigma.z() << "," << r.standing << "\n";
    row.csv = csv.str();
    rows_.push_back(std::move(row));
}

void RunLog::rewindTo(double t)
{
    auto drop = [t](core::Trajectory& traj) {
        traj.poses.erase(std::remove_if(traj.poses.begin(), traj.poses.end(),
                                        [t](const core::TimedPose& p) { return p.t >= t; }),
                         traj.poses.end());
    };
    drop(traj_);
    drop(gt_traj_);
    rows_.erase(std::remove_if(rows_.begin(), rows_.end(), [t](const Row& r) { return r.t >= t; }), rows_.end());
}

std::optional<Eigen::Isometry3d> RunLog::poseAt(double t) const
{
    for (auto it = traj_.poses.rbegin(); it != traj_.poses.rend(); ++it)
        if (it->t == t) return core::toIsometry(it->pose);
    return std::nullopt;
}

std::string RunLog::csv() const
{
    std::string out = kCsvHeader;
    for (const Row& r : rows_) out += r.csv;
    return out;
}

std::string RunLog::summary(size_t frames, int losses, int withdrawn, int relocalizations,
                            double longest_unverified_s, double longest_wait_s) const
{
    std::vector<double> err_m, ms;
    int keyframes = 0, updates = 0, lost_frames = 0;
    for (const Row& r : rows_)
    {
        if (!std::isnan(r.error_m)) err_m.push_back(r.error_m);
        ms.push_back(r.ms);
        keyframes += r.keyframe, updates += r.map_update, lost_frames += r.lost;
    }
    double sq = 0;
    for (double e : err_m) sq += e * e;
    std::ostringstream s;
    s << std::fixed << std::setprecision(3) << "frames      " << frames << " (keyframes " << keyframes
      << ", map updates accepted " << updates << ", frames marked lost " << lost_frames << ")\n"
      << "losses      " << losses << " (withdrawn " << withdrawn << ", relocalizations " << relocalizations
      << "), longest unverified stretch " << longest_unverified_s << " s (fix found after " << longest_wait_s
      << " s of replay)\n"
      << "ATE         RMSE " << 100 * std::sqrt(sq / double(std::max<size_t>(1, err_m.size()))) << " cm, median "
      << 100 * percentile(err_m, 50) << " cm, max " << 100 * percentile(err_m, 100)
      << " cm (map frame, no alignment, vs ground truth at " << err_m.size() << " frames)\n"
      << "time/frame  median " << percentile(ms, 50) << " ms, p90 " << percentile(ms, 90) << " ms, max "
      << percentile(ms, 100) << " ms\n";
    return s.str();
}
}  // namespace quasiloc::app
