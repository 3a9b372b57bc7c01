#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/map/scan_poses.h>
#include <sstream>

#include "file_bytes.h"

namespace quasiloc::map
{
namespace
{
/** The numbers of each non-comment, non-blank line of a text file, with their line numbers. */
std::vector<std::pair<size_t, std::vector<double>>> numberLines(const std::string& path)
{
    core::require(std::filesystem::is_regular_file(path), path, "file not found");
    std::ifstream in(path);
    core::require(in.good(), path, "cannot be opened for reading");
    std::vector<std::pair<size_t, std::vector<double>>> out;
    std::string line;
    for (size_t line_no = 1; std::getline(in, line); ++line_no)
    {
        if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
        const auto words = detail::splitWords(line);
        if (words.empty()) continue;
        std::vector<double> values;
        for (const std::string& w : words)
        {
            double v = 0;
            core::require(detail::parseNumber(w, v) && std::isfinite(v), path + ":" + std::to_string(line_no),
                          "'" + w + "' is not a finite number");
            values.push_back(v);
        }
        out.emplace_back(line_no, std::move(values));
    }
    return out;
}

Eigen::Isometry3d matrixPose(const std::vector<double>& values, const std::string& where)
{
    core::require(values.size() == 12 || values.size() == 16, where,
                  "expected a 3x4 (12 values) or 4x4 (16 values) row-major matrix, got " +
                      std::to_string(values.size()) + " values");
    return core::toIsometry(core::fromMatrixRowMajor(values, where));
}
}  // namespace

Eigen::Isometry3d readCalibrationMatrix(const std::string& path, const std::string& key)
{
    core::require(std::filesystem::is_regular_file(path), path, "file not found");
    std::ifstream in(path);
    std::string line;
    for (size_t line_no = 1; std::getline(in, line); ++line_no)
    {
        const auto colon = line.find(':');
        if (colon == std::string::npos || detail::splitWords(line.substr(0, colon)) != std::vector<std::string>{key})
            continue;
        std::vector<double> values;
        for (const std::string& w : detail::splitWords(line.substr(colon + 1)))
        {
            double v = 0;
            core::require(detail::parseNumber(w, v), path + ":" + std::to_string(line_no),
                          "'" + w + "' is not a number");
            values.push_back(v);
        }
        return matrixPose(values, path + ":" + std::to_string(line_no) + " (" + key + ")");
    }
    throw core::InputError(path, "no line '" + key + ": ...' (the LiDAR's extrinsic)");
}

std::vector<Eigen::Isometry3d> readKittiPoses(const std::string& path)
{
    std::vector<Eigen::Isometry3d> poses;
    for (const auto& [line_no, values] : numberLines(path))
    {
        const std::string where = path + ":" + std::to_string(line_no);
        core::require(values.size() == 12, where,
                      "a KITTI pose line holds 12 numbers (3x4 row-major), not " + std::to_string(values.size()));
        poses.push_back(matrixPose(values, where));
    }
    core::require(!poses.empty(), path, "holds no pose");
    return poses;
}

std::vector<double> readScanTimes(const std::string& path)
{
    std::vector<double> times;
    for (const auto& [line_no, values] : numberLines(path))
    {
        core::require(values.size() == 1, path + ":" + std::to_string(line_no), "expected one time per line");
        times.push_back(values[0]);
    }
    core::require(!times.empty(), path, "holds no time");
    return times;
}

double numberFromFileName(const std::string& path)
{
    std::string stem = std::filesystem::path(path).filename().string();
    if (const auto dot = stem.rfind('.'); dot != std::string::npos && dot > 0) stem.resize(dot);
    double v = 0;
    core::require(detail::parseNumber(stem, v) && std::isfinite(v), path,
                  "the file name does not spell a number (scan_times = names needs names like 1626343512.123.pcd "
                  "or 0000000042.bin)");
    return v;
}

ScanPoses::ScanPoses(const ScanPoseOptions& options, const std::vector<std::string>& scan_names,
                     const std::vector<double>& stamps)
    : options_(options), names_(scan_names)
{
    const size_t n = scan_names.size();
    core::require(options.times != ScanTimeSource::Auto, "ScanPoses", "scan_times = auto must be resolved first");
    std::vector<double> raw(n);
    if (options.times == ScanTimeSource::Stamps)
    {
        core::require(stamps.size() == n, "ScanPoses", "one stamp per scan expected");
        core::require(options.format != TrajectoryFormat::Kitti, options.trajectory,
                      "KITTI poses are numbered by frame, not by time: with stamped scans use a TUM trajectory (or "
                      "scan_times = order / file)");
        raw = stamps;
    }
    if (options.times == ScanTimeSource::TimesFile)
    {
        const std::vector<double> times = readScanTimes(options.times_file);
        core::require(times.size() == n, options.times_file,
                      "lists " + std::to_string(times.size()) + " times for " + std::to_string(n) + " scans");
        raw = times;
    }
    for (size_t i = 0; i < n; ++i)
    {
        if (options.times == ScanTimeSource::FileNames) raw[i] = numberFromFileName(scan_names[i]);
        if (options.times == ScanTimeSource::Order) raw[i] = double(i);
    }
    if (options.format == TrajectoryFormat::Kitti)
    {
        const std::vector<Eigen::Isometry3d> poses = readKittiPoses(options.trajectory);
        for (size_t k = 0; k < poses.size(); ++k)
            trajectory_.poses.push_back({double(k) * options.frame_period_s, core::fromIsometry(poses[k])});
        for (size_t i = 0; i < n; ++i)
        {
            const double frame = raw[i];
            core::require(
                frame >= 0 && frame == std::floor(frame), scan_names[i],
                "with KITTI poses a scan's number is a frame (a whole number >= 0), not " + std::to_string(frame));
            core::require(frame < double(poses.size()), scan_names[i],
                          "needs pose line " + std::to_string(size_t(frame) + 1) + " of " + options.trajectory +
                              ", which holds only " + std::to_string(poses.size()) + " poses");
            stamps_.push_back(frame * options.frame_period_s);
        }
        max_gap_s_ = 1.5 * options.frame_period_s;
    }
    else
    {
        if (options.format == TrajectoryFormat::Bag)
        {
            trajectory_ = options.poses;
            std::stable_sort(trajectory_.poses.begin(), trajectory_.poses.end(),
                             [](const core::TimedPose& a, const core::TimedPose& b) { return a.t < b.t; });
        }
        else
            trajectory_ = core::readTum(options.trajectory);
        core::require(!trajectory_.poses.empty(), options.trajectory, "holds no pose");
        const double scale = options.times == ScanTimeSource::Stamps ? 1.0 : options.time_scale;
        for (size_t i = 0; i < n; ++i) stamps_.push_back(raw[i] * scale);
        max_gap_s_ = options.max_pose_gap_s;
    }
    for (size_t i = 0; i < n; ++i)
        if (!covers(i, 0))
        {
            std::ostringstream s;
            s.precision(15);
            s << "its time " << stamps_[i] << " s has no pose in " << options.trajectory << " (which spans "
              << trajectory_.poses.front().t << " .. " << trajectory_.poses.back().t << " s";
            if (options.format != TrajectoryFormat::Kitti)
                s << ", with gaps of at most max_pose_gap_s = " << max_gap_s_ << " s bridged";
            throw core::InputError(scan_names[i], s.str() + ")");
        }
}

bool ScanPoses::interpolate(double t, Eigen::Isometry3d& T_world_body) const
{
    const auto& P = trajectory_.poses;
    if (P.empty() || t < P.front().t - 1e-9 || t > P.back().t + 1e-9) return false;
    const auto it =
        std::lower_bound(P.begin(), P.end(), t, [](const core::TimedPose& p, double tt) { return p.t < tt; });
    if (it != P.end() && std::abs(it->t - t) <= 1e-9)
    {
        T_world_body = core::toIsometry(it->pose);
        return true;
    }
    if (it == P.begin() || it == P.end())
    {
        T_world_body = core::toIsometry((it == P.end() ? P.back() : P.front()).pose);
        return true;
    }
    if (it->t - (it - 1)->t > max_gap_s_) return false;
    mrpt::poses::CPose3D T;
    if (!core::interpolatePose(trajectory_, t, T, 0)) return false;
    T_world_body = core::toIsometry(T);
    return true;
}

bool ScanPoses::covers(size_t i, double dt_s) const
{
    Eigen::Isometry3d T;
    return interpolate(stamps_.at(i) + dt_s, T);
}

Eigen::Isometry3d ScanPoses::T_world_lidar(size_t i, double dt_s) const
{
    Eigen::Isometry3d T_world_body;
    if (!interpolate(stamps_.at(i) + dt_s, T_world_body))
        throw core::InputError(names_.at(i), "a point's time (scan time + " + std::to_string(dt_s) +
                                                 " s) has no pose in " + options_.trajectory);
    return T_world_body * options_.T_body_lidar;
}

}  // namespace quasiloc::map
