#include <quasiloc/tracking/run_log.h>

#include <quasiloc/core/pose.h>
#include <quasiloc/eval/json_writer.h>
#include <quasiloc/eval/trajectory_metrics.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace quasiloc::tracking
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
    "line_candidates,line_window_px,ms_lines,ms_search,quasi_keypoints,point_factors,ms_points,plane_factors,plane_"
    "candidates,ms_planes,"
    "bg_sigma_x,bg_sigma_y,bg_sigma_z,ba_sigma_x,ba_sigma_y,ba_sigma_z,standing,stereo_map_sigmas,stereo_rejected,"
    "ms_window_solve,ms_window_marginal,point_candidates,point_correct,unverified\n";

RunLog::RunLog() { traj_.header = "quasiloc-track estimate: T_world_cam0 (the left camera in the map frame)"; }

void RunLog::addStart(const dataset::StereoFrame& frame, const Eigen::Isometry3d& T_world_cam0)
{
    traj_.poses.push_back({frame.timestamp, core::fromIsometry(T_world_cam0)});
    if (frame.T_world_cam0) gt_traj_.poses.push_back({frame.timestamp, *frame.T_world_cam0});
}

void RunLog::addFrame(const dataset::StereoFrame& f, const FrameReport& r, double explained_ratio, double ms_check,
                      double ms_search)
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
        << r.acc_bias_sigma.y() << "," << r.acc_bias_sigma.z() << "," << r.standing << "," << r.stereo_map_sigmas << ","
        << r.stereo_rejected << "," << r.ms_window_solve << "," << r.ms_window_marginal << "," << r.point_candidates
        << "," << r.point_correct;
    row.csv = csv.str();
    rows_.push_back(std::move(row));
}

void RunLog::rewindTo(double t)
{
    auto drop = [t](core::Trajectory& traj) {
        traj.poses.erase(
            std::remove_if(traj.poses.begin(), traj.poses.end(), [t](const core::TimedPose& p) { return p.t >= t; }),
            traj.poses.end());
    };
    drop(traj_);
    drop(gt_traj_);
    rows_.erase(std::remove_if(rows_.begin(), rows_.end(), [t](const Row& r) { return r.t >= t; }), rows_.end());
}

void RunLog::markUnverified(double after_t, double up_to_t)
{
    for (Row& r : rows_)
        if (r.t > after_t && r.t <= up_to_t) r.unverified = true;
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
    for (const Row& r : rows_) out += r.csv + (r.unverified ? ",1\n" : ",0\n");
    return out;
}

struct RunLog::Figures
{
    size_t keyframes = 0, updates = 0, lost_frames = 0, unverified_frames = 0;
    eval::AteResult ate;
    double ms_median = NAN, ms_p90 = NAN, ms_p95 = NAN, ms_max = NAN;
};

RunLog::Figures RunLog::figures() const
{
    Figures f;
    // Every logged pose with ground truth, starts included: the poses of trajectory.tum that quasiloc-eval pairs with
    // the ground truth interpolated at their times (both logs hold them in time order, the truth a subsequence).
    std::vector<eval::PosePair> pairs;
    auto truth = gt_traj_.poses.begin();
    for (const core::TimedPose& p : traj_.poses)
    {
        if (truth == gt_traj_.poses.end()) break;
        if (truth->t != p.t) continue;
        pairs.push_back({p.t, p.t, p.pose, truth->pose});
        ++truth;
    }
    std::vector<double> ms;
    for (const Row& r : rows_)
    {
        ms.push_back(r.ms);
        f.keyframes += r.keyframe, f.updates += r.map_update, f.lost_frames += r.lost;
        f.unverified_frames += r.unverified;
    }
    f.ate = eval::computeAte(pairs, eval::Alignment::None);
    f.ms_median = percentile(ms, 50), f.ms_p90 = percentile(ms, 90), f.ms_p95 = percentile(ms, 95);
    f.ms_max = percentile(ms, 100);
    return f;
}

std::string RunLog::summary(const SessionSummary& s) const
{
    const Figures f = figures();
    const eval::ErrorStats& e = f.ate.trans_m;
    std::ostringstream o;
    o << std::fixed << std::setprecision(3) << "frames      " << s.frames << " (keyframes " << f.keyframes
      << ", map updates accepted " << f.updates << ", frames marked lost " << f.lost_frames << ", unverified "
      << f.unverified_frames << ")\n"
      << "losses      " << s.losses << " (withdrawn " << s.withdrawn << ", relocalizations " << s.relocalizations
      << "), longest unverified stretch " << s.longest_unverified_s << " s (fix found after " << s.longest_wait_s
      << " s of replay)\n";
    if (e.count > 0)
        o << "ATE         RMSE " << 100 * e.rmse << " cm, median " << 100 * e.median << " cm, max " << 100 * e.max
          << " cm (map frame, no alignment, vs ground truth at " << e.count << " poses)\n";
    o << "time/frame  median " << f.ms_median << " ms, p90 " << f.ms_p90 << " ms, p95 " << f.ms_p95 << " ms, max "
      << f.ms_max << " ms\n"
      << std::setprecision(1) << "map         " << s.map.points << " points: load " << s.map.load_s << " s, index "
      << s.map.index_s << " s, distance field " << s.map.field_s << " s (" << std::setprecision(0) << s.map.field_mb
      << " MB, "
      << (s.map.field_streamed ? "streamed"
          : s.map.field_sparse ? "sparse"
                               : "dense")
      << "), global localizer set-up " << std::setprecision(1) << s.localizer_setup_s << " s, start search "
      << s.start_search_s << " s\n";
    return o.str();
}

std::string RunLog::summaryJson(const SessionSummary& s) const
{
    const Figures f = figures();
    eval::JsonWriter j;
    j.beginObject();
    j.key("frames").value(s.frames).key("keyframes").value(f.keyframes).key("map_updates").value(f.updates);
    j.key("frames_marked_lost").value(f.lost_frames).key("frames_unverified").value(f.unverified_frames);
    j.key("losses").value(s.losses).key("withdrawn").value(s.withdrawn).key("relocalizations").value(s.relocalizations);
    j.key("longest_unverified_s").value(s.longest_unverified_s).key("longest_wait_s").value(s.longest_wait_s);
    j.key("start").beginObject();
    j.key("t").value(traj_.poses.empty() ? NAN : traj_.poses.front().t);
    j.key("first_frame_t").value(s.t_first_frame ? *s.t_first_frame : NAN);
    j.key("search_s").value(s.start_search_s);
    if (s.T_world_cam0_start_truth && hasGroundTruth())
        j.key("error_m")
            .value(core::translationDistance(s.T_world_cam0_start, *s.T_world_cam0_start_truth))
            .key("error_deg")
            .value(core::rotationDistanceRad(s.T_world_cam0_start, *s.T_world_cam0_start_truth) * 180 / M_PI);
    j.endObject();
    j.key("map").beginObject().key("points").value(s.map.points).key("load_s").value(s.map.load_s);
    j.key("index_s").value(s.map.index_s).key("field_s").value(s.map.field_s).key("field_mb").value(s.map.field_mb);
    j.key("field_layout").value(s.map.field_streamed ? "streamed" : s.map.field_sparse ? "sparse" : "dense");
    j.key("localizer_setup_s").value(s.localizer_setup_s).endObject();
    if (f.ate.trans_m.count > 0)
    {
        j.key("ate").beginObject().key("frame").value("map, no alignment").key("count").value(f.ate.trans_m.count);
        j.key("rmse_m").value(f.ate.trans_m.rmse).key("median_m").value(f.ate.trans_m.median);
        j.key("max_m").value(f.ate.trans_m.max).key("rmse_deg").value(f.ate.rot_deg.rmse).endObject();
    }
    j.key("time_per_frame_ms").beginObject().key("median").value(f.ms_median).key("p90").value(f.ms_p90);
    j.key("p95").value(f.ms_p95);
    j.key("max").value(f.ms_max).endObject();
    j.endObject();
    return j.str() + "\n";
}

}  // namespace quasiloc::tracking
