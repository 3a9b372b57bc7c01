#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/dataset/ground_truth.h>
#include <quasiloc/dataset/timestamps.h>
#include <sstream>

using quasiloc::core::require;

namespace quasiloc::dataset
{
namespace
{
std::vector<std::string> splitCsv(const std::string& line)
{
    std::vector<std::string> fields;
    std::stringstream ss(line);
    std::string f;
    while (std::getline(ss, f, ',')) fields.push_back(f);
    return fields;
}

bool isInteger(const std::string& s)
{
    const auto b = s.find_first_not_of(" \t");
    const auto e = s.find_last_not_of(" \t");
    if (b == std::string::npos) return false;
    for (auto i = b; i <= e; ++i)
        if (!std::isdigit(static_cast<unsigned char>(s[i]))) return false;
    return true;
}

/** First data line (not empty, not a '#' comment), or "" for a file without data. */
std::string firstDataLine(const std::string& path)
{
    std::ifstream in(path);
    require(in.good(), path, "ground truth file not found or unreadable");
    std::string line;
    while (std::getline(in, line))
    {
        const auto first = line.find_first_not_of(" \t\r");
        if (first != std::string::npos && line[first] != '#') return line;
    }
    return "";
}

bool looksLikeEurocBodyCsv(const std::string& line)
{
    const auto fields = splitCsv(line);
    // Nanosecond timestamps are integers of 16+ digits; TUM rows hold 8 fields of decimal seconds.
    return fields.size() >= 8 && isInteger(fields[0]) &&
           std::count_if(fields[0].begin(), fields[0].end(), [](unsigned char c) { return std::isdigit(c); }) >= 16;
}

/** T_world_body rows of a state_groundtruth_estimate0/data.csv: t_ns, p_xyz, q_wxyz, ... */
core::Trajectory readEurocBodyCsv(const std::string& path)
{
    std::ifstream in(path);
    require(in.good(), path, "ground truth file not found or unreadable");
    core::Trajectory traj;
    std::string line;
    int line_no = 0;
    while (std::getline(in, line))
    {
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        const auto first = line.find_first_not_of(" \t");
        if (first == std::string::npos || line[first] == '#') continue;
        const std::string where = path + ":" + std::to_string(line_no);
        const auto fields = splitCsv(line);
        require(fields.size() >= 8 && isInteger(fields[0]), where,
                "expected 't_ns, p_x, p_y, p_z, q_w, q_x, q_y, q_z, ...' (EuRoC state_groundtruth_estimate0)");
        double v[7];
        for (int i = 0; i < 7; ++i)
        {
            try
            {
                v[i] = std::stod(fields[i + 1]);
            }
            catch (const std::exception&)
            {
                throw core::InputError(where, "field " + std::to_string(i + 2) + " is not a number");
            }
            require(std::isfinite(v[i]), where, "non-finite value");
        }
        const Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
        require(std::abs(q.norm() - 1.0) < 1e-2, where, "quaternion is not unit length");
        traj.poses.push_back(
            {nsToSeconds(std::stoll(fields[0])), core::fromTranslationQuaternion({v[0], v[1], v[2]}, q)});
    }
    std::stable_sort(traj.poses.begin(), traj.poses.end(),
                     [](const core::TimedPose& a, const core::TimedPose& b) { return a.t < b.t; });
    return traj;
}

size_t dropRepeatedTimestamps(core::Trajectory& traj)
{
    const size_t before = traj.poses.size();
    traj.poses.erase(std::unique(traj.poses.begin(), traj.poses.end(),
                                 [](const core::TimedPose& a, const core::TimedPose& b) { return a.t == b.t; }),
                     traj.poses.end());
    return before - traj.poses.size();
}
}  // namespace

GroundTruthFile readGroundTruthCam0(const std::string& path, const mrpt::poses::CPose3D& T_body_cam0)
{
    const std::string first = firstDataLine(path);
    require(!first.empty(), path, "ground truth file holds no pose");
    GroundTruthFile gt;
    if (looksLikeEurocBodyCsv(first))
    {
        gt.kind = GroundTruthFile::Kind::EurocBody;
        gt.T_world_cam0 = readEurocBodyCsv(path);
        for (auto& p : gt.T_world_cam0.poses) p.pose = p.pose + T_body_cam0;  // T_world_body * T_body_cam0
        gt.T_world_cam0.header = "T_world_cam0 (EuRoC body ground truth " + path + " times T_body_cam0)";
    }
    else
    {
        gt.kind = GroundTruthFile::Kind::TumCam0;
        gt.T_world_cam0 = core::readTum(path);
        gt.T_world_cam0.header = "T_world_cam0 (from " + path + ")";
    }
    // gt_sync files repeat the first sample (same timestamp) for every image before ground truth begins.
    gt.duplicate_rows_dropped = dropRepeatedTimestamps(gt.T_world_cam0);
    require(!gt.T_world_cam0.poses.empty(), path, "ground truth file holds no pose");
    return gt;
}

core::Trajectory restrictToSpan(const core::Trajectory& traj, double t0, double t1, double margin_s)
{
    core::Trajectory out;
    out.header = traj.header;
    for (const auto& p : traj.poses)
        if (p.t >= t0 - margin_s && p.t <= t1 + margin_s) out.poses.push_back(p);
    return out;
}

std::optional<mrpt::poses::CPose3D> poseAt(const core::Trajectory& traj, double t, double max_dt_s)
{
    const auto& P = traj.poses;
    if (P.empty()) return std::nullopt;
    const auto it =
        std::lower_bound(P.begin(), P.end(), t, [](const core::TimedPose& p, double tt) { return p.t < tt; });
    double nearest_dt = std::numeric_limits<double>::infinity();
    if (it != P.end()) nearest_dt = std::min(nearest_dt, it->t - t);
    if (it != P.begin()) nearest_dt = std::min(nearest_dt, t - (it - 1)->t);
    if (!(nearest_dt <= max_dt_s)) return std::nullopt;
    mrpt::poses::CPose3D out;
    if (!core::interpolatePose(traj, t, out, max_dt_s)) return std::nullopt;
    return out;
}

}  // namespace quasiloc::dataset
