// bag2rawlog: ROS 1 or ROS 2 bag (+ Kalibr calibration, or the bag's CameraInfo and /tf_static) -> MRPT rawlog
// (+ <name>_Images/), calibration INI, ground truth TUM.
#include <mrpt/system/CTimeLogger.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <quasiloc/core/program_options.h>
#include <quasiloc/ros/bag2rawlog.h>

namespace fs = std::filesystem;
using namespace quasiloc;

namespace
{
const char* kUsage =
    "Usage: bag2rawlog <config.ini> [--set Bag2Rawlog.key=value]... [--print-timing]\n"
    "Reads a ROS 1 bag or a ROS 2 bag (a rosbag2 folder, or one .db3 / .mcap file: left and right images, IMU,\n"
    "optional ground truth; topics from [Bag2Rawlog]) and writes the stereo + IMU rawlog quasiloc-track reads, its\n"
    "images in <output>_Images/, the calibration INI (<output>_calib.ini) from a Kalibr camchain, or from the bag's\n"
    "CameraInfo and /tf_static, with the IMU noise model of a Kalibr IMU YAML or an INI's [imu] section, the ground\n"
    "truth as TUM of T_world_cam0 (<output>_gt_cam0.tum) and the effective configuration (<output>_bag2rawlog.ini).\n"
    "See docs/bag2rawlog.md.";
const char* kSection = "Bag2Rawlog";

void printResult(const ros::Bag2RawlogResult& r, double seconds)
{
    std::printf("bag:                   %s, %.1f MB; %s %zu (%s), right %zu (%s), IMU %zu, ground truth %zu messages\n",
                r.bag_format.c_str(), r.bag_bytes / 1e6, "left", r.left_msgs, r.left_type.c_str(), r.right_msgs,
                r.right_type.c_str(), r.imu_msgs, r.gt_msgs);
    std::printf("stereo frames written: %zu (largest left-right offset %.3f ms)\n", r.stereo_written,
                r.max_pair_offset_ms);
    std::printf("unpaired images:       %zu left, %zu right (%zu of them out of order)\n", r.unpaired_left,
                r.unpaired_right, r.out_of_order);
    for (const auto& line : r.unpaired_report) std::printf("  %s\n", line.c_str());
    if (r.unpaired_left + r.unpaired_right > r.unpaired_report.size()) std::printf("  ...\n");
    std::printf("IMU samples written:   %zu (%zu observations later than the reorder window: dropped)\n", r.imu_written,
                r.late_dropped);
    std::printf("frames span:           %lld .. %lld ns\n", static_cast<long long>(r.first_frame_ns),
                static_cast<long long>(r.last_frame_ns));
    std::printf("rawlog:                %s (images in %s)\n", r.rawlog_path.c_str(), r.images_folder.c_str());
    std::printf("calibration:           %s\n", r.calib_path.c_str());
    if (!r.gt_path.empty()) std::printf("ground truth:          %s (%zu poses)\n", r.gt_path.c_str(), r.gt_written);
    std::printf("time taken:            %.2f s (%.1f MB/s of bag, %.1f stereo frames/s)\n", seconds,
                r.bag_bytes / 1e6 / seconds, r.stereo_written / seconds);
}

int run(const core::CommandLine& cmd)
{
    const auto cfg = core::loadConfig(cmd);
    ros::Bag2RawlogOptions options;
    core::loadOptionsChecked(options, cfg, kSection, cmd.config_path);
    options.check();

    mrpt::system::CTimeLogger timer(cmd.print_timing, "bag2rawlog");
    const auto start = std::chrono::steady_clock::now();
    const auto result = ros::convertBagToRawlog(options, &timer);
    const fs::path out(options.output);
    core::writeEffectiveConfig((out.parent_path() / (out.stem().string() + "_bag2rawlog.ini")).string(),
                               {{kSection, &options}}, "effective configuration of bag2rawlog");
    printResult(result, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    if (cmd.print_timing) std::cout << timer.getStatsAsText();
    timer.clear(/*deep_clear=*/true);
    return 0;
}
}  // namespace

int main(int argc, char** argv) { return core::runProgram(argc, argv, kUsage, run); }
