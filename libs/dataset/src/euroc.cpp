#include <algorithm>
#include <filesystem>
#include <map>
#include <quasiloc/core/error.h>
#include <quasiloc/dataset/euroc.h>
#include <quasiloc/dataset/euroc_imu_csv.h>

#include "euroc_csv.h"

namespace fs = std::filesystem;
using quasiloc::core::require;

namespace quasiloc::dataset
{
namespace
{
/** cam<i>/data.csv: timestamp -> image path (only rows whose image file exists); the others go to `missing`. */
std::map<std::int64_t, std::string> readCameraCsv(const std::string& cam_folder, size_t& rows,
                                                  std::vector<std::int64_t>& missing)
{
    const std::string csv_path = cam_folder + "/data.csv";
    std::map<std::int64_t, std::string> images;
    const auto lines = csv::readLines(csv_path);
    rows = lines.size();
    for (const auto& l : lines)
    {
        const std::string where = csv::where(csv_path, l);
        require(l.fields.size() == 2, where, "expected 'timestamp_ns,filename'");
        const std::int64_t t = csv::parseTimestampNs(l.fields[0], where);
        require(!images.count(t), where, "timestamp appears twice");
        const std::string png = cam_folder + "/data/" + l.fields[1];
        if (fs::is_regular_file(png))
            images[t] = png;
        else
            missing.push_back(t);
    }
    return images;
}

void addSkipped(EurocSequence& seq, const std::string& reason, std::vector<std::int64_t> t_ns)
{
    if (t_ns.empty()) return;
    std::sort(t_ns.begin(), t_ns.end());
    seq.skipped.push_back({reason, std::move(t_ns)});
}
}  // namespace

size_t EurocSequence::numSkippedRows() const
{
    size_t n = 0;
    for (const auto& s : skipped) n += s.t_ns.size();
    return n;
}

std::vector<std::string> EurocSequence::skippedRowsReport() const
{
    constexpr size_t kShown = 5;
    std::vector<std::string> lines;
    for (const auto& s : skipped)
    {
        std::string line = std::to_string(s.t_ns.size()) + " " + s.reason + " (skipped): t_ns=";
        for (size_t i = 0; i < s.t_ns.size() && i < kShown; ++i) line += (i ? ", " : "") + std::to_string(s.t_ns[i]);
        if (s.t_ns.size() > kShown) line += ", ...";
        lines.push_back(line);
    }
    return lines;
}

std::string eurocMav0Folder(const std::string& asl_folder)
{
    require(fs::is_directory(asl_folder), asl_folder, "EuRoC ASL folder not found");
    if (fs::is_directory(fs::path(asl_folder) / "mav0" / "cam0")) return (fs::path(asl_folder) / "mav0").string();
    require(fs::is_directory(fs::path(asl_folder) / "cam0"), asl_folder,
            "not an EuRoC ASL folder (neither mav0/cam0/ nor cam0/ inside)");
    return asl_folder;
}

EurocSequence readEurocSequence(const std::string& asl_folder)
{
    EurocSequence seq;
    seq.mav0_folder = eurocMav0Folder(asl_folder);
    const std::string cam0 = seq.mav0_folder + "/cam0", cam1 = seq.mav0_folder + "/cam1";
    seq.rig = core::StereoRig::fromEuroc(cam0 + "/sensor.yaml", cam1 + "/sensor.yaml");

    std::vector<std::int64_t> cam0_missing, cam1_missing, cam0_unmatched, cam1_unmatched;
    const auto left = readCameraCsv(cam0, seq.cam0_rows, cam0_missing);
    const auto right = readCameraCsv(cam1, seq.cam1_rows, cam1_missing);
    for (const auto& [t, png] : left)
    {
        const auto r = right.find(t);
        if (r == right.end())
            cam0_unmatched.push_back(t);
        else
            seq.pairs.push_back({t, png, r->second});
    }
    for (const auto& [t, png] : right)
        if (!left.count(t)) cam1_unmatched.push_back(t);
    addSkipped(seq, "cam0/data.csv rows whose image file is missing", cam0_missing);
    addSkipped(seq, "cam1/data.csv rows whose image file is missing", cam1_missing);
    addSkipped(seq, "cam0/data.csv rows without a cam1 image at the same timestamp", cam0_unmatched);
    addSkipped(seq, "cam1/data.csv rows without a cam0 image at the same timestamp", cam1_unmatched);
    require(!seq.pairs.empty(), seq.mav0_folder, "no stereo pair: no cam0 and cam1 images share a timestamp");

    EurocImuCsv imu = readEurocImuCsv(seq.mav0_folder + "/imu0/data.csv", kEurocImuRateHz);
    seq.imu_t_ns = std::move(imu.t_ns);
    seq.imu = std::move(imu.samples);
    return seq;
}

}  // namespace quasiloc::dataset
