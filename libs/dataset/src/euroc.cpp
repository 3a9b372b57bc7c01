#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <quasiloc/core/error.h>
#include <quasiloc/dataset/euroc.h>
#include <quasiloc/dataset/timestamps.h>
#include <sstream>

namespace fs = std::filesystem;
using quasiloc::core::require;

namespace quasiloc::dataset
{
namespace
{
struct CsvLine
{
    int line_no;
    std::vector<std::string> fields;  ///< trimmed
};

std::string trim(const std::string& s)
{
    const auto b = s.find_first_not_of(" \t\r");
    if (b == std::string::npos) return "";
    const auto e = s.find_last_not_of(" \t\r");
    return s.substr(b, e - b + 1);
}

/** Data lines of a csv file (comments '#' and blank lines skipped). */
std::vector<CsvLine> readCsv(const std::string& path)
{
    require(fs::is_regular_file(path), path, "csv file not found");
    std::ifstream in(path);
    require(in.good(), path, "csv file unreadable");
    std::vector<CsvLine> rows;
    std::string line;
    int line_no = 0;
    while (std::getline(in, line))
    {
        ++line_no;
        const std::string t = trim(line);
        if (t.empty() || t[0] == '#') continue;
        CsvLine row{line_no, {}};
        std::stringstream ss(t);
        std::string f;
        while (std::getline(ss, f, ',')) row.fields.push_back(trim(f));
        rows.push_back(std::move(row));
    }
    return rows;
}

std::int64_t parseTimestampNs(const std::string& s, const std::string& where)
{
    require(!s.empty() && s.find_first_not_of("0123456789") == std::string::npos, where,
            "timestamp '" + s + "' is not an integer number of nanoseconds");
    try
    {
        return std::stoll(s);
    }
    catch (const std::exception&)
    {
        throw core::InputError(where, "timestamp '" + s + "' out of range");
    }
}

double parseFinite(const std::string& s, const std::string& where)
{
    size_t used = 0;
    double v = 0;
    try
    {
        v = std::stod(s, &used);
    }
    catch (const std::exception&)
    {
        used = 0;
    }
    require(used == s.size() && used > 0 && std::isfinite(v), where, "'" + s + "' is not a finite number");
    return v;
}

/** cam<i>/data.csv: timestamp -> image path (only rows whose image file exists); the others go to `missing`. */
std::map<std::int64_t, std::string> readCameraCsv(const std::string& cam_folder, size_t& rows,
                                                  std::vector<std::int64_t>& missing)
{
    const std::string csv = cam_folder + "/data.csv";
    std::map<std::int64_t, std::string> images;
    const auto lines = readCsv(csv);
    rows = lines.size();
    for (const auto& l : lines)
    {
        const std::string where = csv + ":" + std::to_string(l.line_no);
        require(l.fields.size() == 2, where, "expected 'timestamp_ns,filename'");
        const std::int64_t t = parseTimestampNs(l.fields[0], where);
        require(!images.count(t), where, "timestamp appears twice");
        const std::string png = cam_folder + "/data/" + l.fields[1];
        if (fs::is_regular_file(png))
            images[t] = png;
        else
            missing.push_back(t);
    }
    return images;
}

void readImuCsv(const std::string& csv, EurocSequence& seq)
{
    for (const auto& l : readCsv(csv))
    {
        const std::string where = csv + ":" + std::to_string(l.line_no);
        require(l.fields.size() == 7, where, "expected 7 columns 't_ns, w_x, w_y, w_z, a_x, a_y, a_z'");
        const std::int64_t t = parseTimestampNs(l.fields[0], where);
        require(seq.imu_t_ns.empty() || t > seq.imu_t_ns.back(), where, "IMU timestamps must increase");
        ImuSample s;
        s.t = nsToSeconds(t);
        // EuRoC puts the angular rate first: w_RS_S_xyz [rad/s], then a_RS_S_xyz [m/s^2].
        s.gyro = {parseFinite(l.fields[1], where), parseFinite(l.fields[2], where), parseFinite(l.fields[3], where)};
        s.acc = {parseFinite(l.fields[4], where), parseFinite(l.fields[5], where), parseFinite(l.fields[6], where)};
        seq.imu_t_ns.push_back(t);
        seq.imu.push_back(s);
    }
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

    readImuCsv(seq.mav0_folder + "/imu0/data.csv", seq);
    require(!seq.imu.empty(), seq.mav0_folder + "/imu0/data.csv", "holds no IMU sample");
    return seq;
}

}  // namespace quasiloc::dataset
