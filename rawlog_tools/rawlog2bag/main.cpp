// rawlog2bag: stereo + IMU rawlog (+ calibration INI, ground truth) -> ROS 1 bag or ROS 2 bag (rosbag2 folder, MCAP)
// with Kalibr YAML files beside it.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <quasiloc/core/program_options.h>
#include <quasiloc/ros/rawlog2bag.h>

namespace fs = std::filesystem;
using namespace quasiloc;

namespace
{
const char* kUsage =
    "Usage: rawlog2bag <config.ini> [--set Rawlog2Bag.key=value]... [--print-timing]\n"
    "Writes a stereo + IMU rawlog (e.g. sim-rawlog's) as a ROS 1 bag, or with format=mcap as a ROS 2 bag (a rosbag2\n"
    "folder: metadata.yaml + one MCAP file, with CameraInfo and /tf_static): images (mono8, mono16, png or jpeg), IMU\n"
    "and, with [Rawlog2Bag] groundtruth, the ground truth as PoseStamped of the body frame. Beside the bag: the\n"
    "calibration as Kalibr camchain and IMU YAML (<bag>_camchain.yaml, <bag>_imu.yaml) and the effective\n"
    "configuration (<bag>_rawlog2bag.ini). bag2rawlog reads them back. See docs/bag2rawlog.md.";
const char* kSection = "Rawlog2Bag";

int run(const core::CommandLine& cmd)
{
    const auto cfg = core::loadConfig(cmd);
    ros::Rawlog2BagOptions options;
    core::loadOptionsChecked(options, cfg, kSection, cmd.config_path);
    options.check();
    const auto start = std::chrono::steady_clock::now();
    const auto r = ros::convertRawlogToBag(options);
    const fs::path out(options.output_bag);
    core::writeEffectiveConfig((out.parent_path() / (out.stem().string() + "_rawlog2bag.ini")).string(),
                               {{kSection, &options}}, "effective configuration of rawlog2bag");
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("stereo frames written: %zu\n", r.stereo_written);
    std::printf("IMU samples written:   %zu\n", r.imu_written);
    std::printf("ground truth poses:    %zu\n", r.gt_written);
    if (r.ignored)
        std::printf("observations ignored:  %zu (neither stereo with a right image nor full IMU)\n", r.ignored);
    std::printf("bag:                   %s (%.1f MB)\n", r.bag_path.c_str(), r.bag_bytes / 1e6);
    std::printf("Kalibr calibration:    %s, %s\n", r.camchain_path.c_str(), r.imu_yaml_path.c_str());
    std::printf("time taken:            %.2f s (%.1f MB/s of bag, %.1f stereo frames/s)\n", seconds,
                r.bag_bytes / 1e6 / seconds, r.stereo_written / seconds);
    return 0;
}
}  // namespace

int main(int argc, char** argv) { return core::runProgram(argc, argv, kUsage, run); }
