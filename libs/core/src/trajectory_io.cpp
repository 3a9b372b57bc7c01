#include <algorithm>
#include <cmath>
#include <fstream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/core/trajectory_io.h>
#include <sstream>

namespace quasiloc::core
{
Trajectory readTum(const std::string& path)
{
    std::ifstream in(path);
    require(in.good(), path, "TUM trajectory file not found or unreadable");
    Trajectory traj;
    std::string line;
    int line_no = 0;
    while (std::getline(in, line))
    {
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        const auto first = line.find_first_not_of(" \t");
        if (first == std::string::npos) continue;
        if (line[first] == '#')
        {
            traj.header += (traj.header.empty() ? "" : "\n") + line.substr(first + 1);
            continue;
        }
        std::replace(line.begin(), line.end(), ',', ' ');
        std::istringstream ss(line);
        double v[8];
        int n = 0;
        while (n < 8 && ss >> v[n]) ++n;
        std::string extra;
        const std::string where = path + ":" + std::to_string(line_no);
        require(n == 8 && !(ss >> extra), where, "expected 8 numbers 't tx ty tz qx qy qz qw'");
        for (double x : v) require(std::isfinite(x), where, "non-finite value");
        const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
        require(std::abs(q.norm() - 1.0) < 1e-2, where, "quaternion is not unit length");
        traj.poses.push_back({v[0], fromTranslationQuaternion({v[1], v[2], v[3]}, q)});
    }
    std::stable_sort(traj.poses.begin(), traj.poses.end(),
                     [](const TimedPose& a, const TimedPose& b) { return a.t < b.t; });
    return traj;
}

void writeTum(const std::string& path, const Trajectory& traj)
{
    std::ostringstream out;
    if (!traj.header.empty())
    {
        std::istringstream hs(traj.header);
        std::string l;
        while (std::getline(hs, l)) out << "#" << (l.empty() || l[0] == ' ' ? "" : " ") << l << "\n";
    }
    char buf[256];
    for (const auto& p : traj.poses)
    {
        const Eigen::Quaterniond q = quaternionOf(p.pose);
        std::snprintf(buf, sizeof(buf), "%.9f %.7f %.7f %.7f %.9f %.9f %.9f %.9f\n", p.t, p.pose.x(), p.pose.y(),
                      p.pose.z(), q.x(), q.y(), q.z(), q.w());
        out << buf;
    }
    writeTextFileAtomically(path, out.str());
}

bool interpolatePose(const Trajectory& traj, double t, mrpt::poses::CPose3D& out, double max_extrapolation_s)
{
    const auto& P = traj.poses;
    if (P.empty()) return false;
    if (t <= P.front().t)
    {
        if (P.front().t - t > max_extrapolation_s) return false;
        out = P.front().pose;
        return true;
    }
    if (t >= P.back().t)
    {
        if (t - P.back().t > max_extrapolation_s) return false;
        out = P.back().pose;
        return true;
    }
    const auto it = std::upper_bound(P.begin(), P.end(), t, [](double tt, const TimedPose& p) { return tt < p.t; });
    const TimedPose& b = *it;
    const TimedPose& a = *(it - 1);
    const double dt = b.t - a.t;
    const double s = dt > 0 ? (t - a.t) / dt : 0.0;
    const Eigen::Quaterniond q = quaternionOf(a.pose).slerp(s, quaternionOf(b.pose));
    const Eigen::Vector3d ta(a.pose.x(), a.pose.y(), a.pose.z()), tb(b.pose.x(), b.pose.y(), b.pose.z());
    out = fromTranslationQuaternion((1 - s) * ta + s * tb, q);
    return true;
}

}  // namespace quasiloc::core
