// euroc2rawlog: EuRoC ASL folder -> MRPT rawlog (+ <name>_Images/), calibration INI, ground truth TUM.
#include <mrpt/system/CTimeLogger.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/dataset/euroc_conversion.h>

namespace fs = std::filesystem;
using namespace quasiloc;

namespace
{
const char* kUsage =
    "Usage:\n"
    "  euroc2rawlog <config.ini> [--set Euroc2Rawlog.key=value]... [--print-timing]\n"
    "  euroc2rawlog --input ASL_FOLDER --output OUT.rawlog [--groundtruth FILE] [--calib-out FILE.ini]\n"
    "               [--gt-out FILE.tum] [--imu-yaml FILE] [--max-frames N] [--print-timing]\n"
    "Converts an EuRoC ASL folder (mav0/cam0, cam1, imu0) into an MRPT rawlog with the images as PNG in\n"
    "<OUT>_Images/, the calibration INI (default <OUT>_calib.ini) and, with --groundtruth (TUM of T_world_cam0\n"
    "or EuRoC state_groundtruth_estimate0/data.csv), a TUM file of T_world_cam0 (default <OUT>_gt_cam0.tum).\n"
    "The effective configuration is written to <OUT>_euroc2rawlog.ini.";
const char* kSection = "Euroc2Rawlog";

/** Plain flags become overrides of [Euroc2Rawlog]; a first argument that is not a flag is the INI file. */
core::CommandLine withFlagsAsOverrides(core::CommandLine cmd)
{
    static const std::map<std::string, std::string> kFlagKeys = {
        {"--input", "input"},         {"--output", "output"}, {"--groundtruth", "groundtruth"},
        {"--calib-out", "calib_out"}, {"--gt-out", "gt_out"}, {"--max-frames", "max_frames"},
        {"--imu-yaml", "imu_yaml"}};
    const auto& f = cmd.flags;
    size_t i = 0;
    if (!f.empty() && f[0].rfind("--", 0) != 0) cmd.config_path = f[i++];
    for (; i < f.size(); ++i)
    {
        const auto key = kFlagKeys.find(f[i]);
        core::require(key != kFlagKeys.end(), "command line (" + f[i] + ")", "unknown argument; see --help");
        core::require(i + 1 < f.size(), "command line (" + f[i] + ")", "needs a value");
        cmd.overrides.emplace_back(std::string(kSection) + "." + key->second, f[++i]);
    }
    cmd.flags.clear();
    return cmd;
}

uintmax_t folderBytes(const std::string& folder)
{
    uintmax_t n = 0;
    for (const auto& e : fs::recursive_directory_iterator(folder))
        if (e.is_regular_file()) n += e.file_size();
    return n;
}

std::string megabytes(uintmax_t bytes)
{
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%.1f MB", bytes / 1e6);
    return buf;
}

void printResult(const dataset::Euroc2RawlogResult& r, double seconds)
{
    std::printf("stereo frames written: %zu (cam0 rows %zu, cam1 rows %zu)\n", r.stereo_written, r.cam0_rows,
                r.cam1_rows);
    std::printf("IMU samples written:   %zu (imu0 rows %zu)\n", r.imu_written, r.imu_rows);
    std::printf("skipped csv rows:      %zu\n", r.skipped_rows);
    for (const auto& line : r.skipped_rows_report) std::printf("  %s\n", line.c_str());
    std::printf("frames span:           %.6f .. %.6f s\n", r.first_frame_t, r.last_frame_t);
    if (!r.gt_path.empty())
    {
        std::printf("ground truth (%s): %zu poses %.6f .. %.6f s written to %s", r.gt_kind.c_str(), r.gt_poses_written,
                    r.gt_first_t, r.gt_last_t, r.gt_path.c_str());
        std::printf("\n  (%zu rows of the input repeat an earlier timestamp: dropped)\n", r.gt_duplicate_rows_dropped);
        std::printf("frames with a ground-truth pose (within 5 ms): %zu of %zu\n", r.frames_with_gt, r.stereo_written);
    }
    std::printf("rawlog:                %s (%s)\n", r.rawlog_path.c_str(),
                megabytes(fs::file_size(r.rawlog_path)).c_str());
    std::printf("images:                %s (%s)\n", r.images_folder.c_str(),
                megabytes(folderBytes(r.images_folder)).c_str());
    std::printf("calibration:           %s (IMU noise model from %s)\n", r.calib_path.c_str(), r.imu_yaml.c_str());
    std::printf("time taken:            %.2f s\n", seconds);
}

int run(const core::CommandLine& raw_cmd)
{
    const core::CommandLine cmd = withFlagsAsOverrides(raw_cmd);
    const auto cfg = core::loadConfig(cmd);
    dataset::Euroc2RawlogOptions options;
    core::loadOptionsChecked(options, cfg, kSection, cmd.config_path.empty() ? "command line" : cmd.config_path);
    options.check();

    mrpt::system::CTimeLogger timer(cmd.print_timing, "euroc2rawlog");
    const auto start = std::chrono::steady_clock::now();
    const auto result = dataset::convertEurocToRawlog(options, &timer);
    const fs::path out(options.output);
    core::writeEffectiveConfig((out.parent_path() / (out.stem().string() + "_euroc2rawlog.ini")).string(),
                               {{kSection, &options}}, "effective configuration of euroc2rawlog");
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    printResult(result, seconds);
    if (cmd.print_timing) std::cout << timer.getStatsAsText();
    timer.clear(/*deep_clear=*/true);  // printed above: keep the destructor from dumping it again
    return 0;
}
}  // namespace

int main(int argc, char** argv) { return core::runProgram(argc, argv, kUsage, run, /*config_required=*/false); }
