#include "run_log.h"

#include <quasiloc/core/pose.h>

#include <algorithm>
#include <cmath>
#include <iomanip>

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

RunLog::RunLog()
{
    traj_.header = "quasiloc-track estimate: T_world_cam0 (the left camera in the map frame)";
    csv_ << "t,keyframe,map_update,correction_m,correction_deg,edge_inlier_ratio,edge_points,prior_sigma_m,"
            "prior_sigma_deg,lost,landmarks,error_m,error_deg,ms_predict,ms_image,ms_align,ms_visual,ms_window,ms_total,"
            "bg_x,bg_y,bg_z,ba_x,ba_y,ba_z,stereo_map_points,explained_ratio,ms_check,camera_lines,map_lines,line_factors,"
            "line_candidates,line_window_px,ms_lines\n";
}

void RunLog::addStart(const dataset::StereoFrame& frame, const Eigen::Isometry3d& T_world_cam0)
{
    traj_.poses.push_back({frame.timestamp, core::fromIsometry(T_world_cam0)});
    if (frame.T_world_cam0) gt_traj_.poses.push_back({frame.timestamp, *frame.T_world_cam0});
}

void RunLog::addFrame(const dataset::StereoFrame& f, const tracking::FrameReport& r, double explained_ratio,
                      double ms_check)
{
    traj_.poses.push_back({r.t, core::fromIsometry(r.T_world_cam0)});
    double e_m = NAN, e_deg = NAN;
    if (f.T_world_cam0)
    {
        const Eigen::Isometry3d G = core::toIsometry(*f.T_world_cam0);
        e_m = core::translationDistance(r.T_world_cam0, G);
        e_deg = core::rotationDistanceRad(r.T_world_cam0, G) * 180 / M_PI;
        err_m_.push_back(e_m);
        gt_traj_.poses.push_back({r.t, *f.T_world_cam0});
    }
    last_error_m_ = e_m;
    ms_.push_back(r.ms_total + ms_check);
    updates_ += r.map_update, keyframes_ += r.keyframe, lost_frames_ += r.lost;
    csv_ << std::setprecision(17) << r.t << std::setprecision(6) << "," << r.keyframe << "," << r.map_update << ","
         << r.correction_m << "," << r.correction_deg << "," << r.edge_inlier_ratio << "," << r.edge_points << ","
         << r.prior_sigma_m << "," << r.prior_sigma_deg << "," << r.lost << "," << r.landmarks << "," << e_m << ","
         << e_deg << "," << r.ms_predict << "," << r.ms_image << "," << r.ms_align << "," << r.ms_visual << ","
         << r.ms_window << "," << r.ms_total << "," << r.gyro_bias.x() << "," << r.gyro_bias.y() << ","
         << r.gyro_bias.z() << "," << r.acc_bias.x() << "," << r.acc_bias.y() << "," << r.acc_bias.z() << ","
         << r.stereo_map_points << "," << explained_ratio << "," << ms_check << "," << r.camera_lines << ","
         << r.map_lines << "," << r.line_factors << "," << r.line_candidates << "," << r.line_window_px << ","
         << r.ms_lines << "\n";
}

std::string RunLog::summary(size_t frames, int relocalizations, double longest_unverified_s) const
{
    double sq = 0;
    for (double e : err_m_) sq += e * e;
    std::ostringstream s;
    s << std::fixed << std::setprecision(3) << "frames      " << frames << " (keyframes " << keyframes_
      << ", map updates accepted " << updates_ << ", frames marked lost " << lost_frames_ << ", relocalizations "
      << relocalizations << ", longest unverified stretch before a relocalization " << longest_unverified_s << " s)\n"
      << "ATE         RMSE " << 100 * std::sqrt(sq / double(std::max<size_t>(1, err_m_.size()))) << " cm, median "
      << 100 * percentile(err_m_, 50) << " cm, max " << 100 * percentile(err_m_, 100)
      << " cm (map frame, no alignment, vs ground truth at " << err_m_.size() << " frames)\n"
      << "time/frame  median " << percentile(ms_, 50) << " ms, p90 " << percentile(ms_, 90) << " ms, max "
      << percentile(ms_, 100) << " ms\n";
    return s.str();
}
}  // namespace quasiloc::app
