#include "kitti_sequence.h"

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/map/map_import.h>
#include <sstream>

namespace quasiloc::bench
{
namespace
{
std::vector<double> readNumbers(std::istringstream& in)
{
    std::vector<double> v;
    for (double x; in >> x;) v.push_back(x);
    return v;
}

core::CameraModel readCamera(const std::string& path, const cv::Size& size)
{
    std::ifstream f(path);
    core::require(f.good(), path, "cannot open the calibration file");
    for (std::string line; std::getline(f, line);)
    {
        std::istringstream in(line);
        std::string key;
        in >> key;
        if (key != "K_cam2:") continue;
        const std::vector<double> K = readNumbers(in);
        core::require(K.size() == 9, path, "K_cam2 must have 9 values");
        return core::CameraModel::pinhole(size.width, size.height, K[0], K[4], K[2], K[5]);
    }
    throw core::InputError(path, "no K_cam2 line");
}

std::vector<Eigen::Isometry3d> readPoses(const std::string& path)
{
    std::ifstream f(path);
    core::require(f.good(), path, "cannot open the pose file");
    std::vector<Eigen::Isometry3d> poses;
    int line_no = 0;
    for (std::string line; std::getline(f, line);)
    {
        ++line_no;
        if (line.empty() || line[0] == '#') continue;
        std::istringstream in(line);
        poses.push_back(
            core::toIsometry(core::fromMatrixRowMajor(readNumbers(in), path + ":" + std::to_string(line_no))));
    }
    core::require(!poses.empty(), path, "no pose");
    return poses;
}
}  // namespace

CrossModalSequence loadKittiSequence(const std::string& dir, int max_frames, const std::string& map_path)
{
    CrossModalSequence s;
    s.name = "kitti_raw_seq78";
    const std::string path = map_path.empty() ? dir + "/map_even_frames_5cm.ply" : map_path;
    if (path.size() > 4 && path.compare(path.size() - 4, 4, ".map") == 0)
        s.map = map::LidarMap::load(path);
    else
        s.map = map::importCloud(path, map::ImportOptions{}).map;
    const std::vector<Eigen::Isometry3d> poses = readPoses(dir + "/poses_cam2.txt");
    std::vector<int> frames;
    for (int k = 1; k < int(poses.size()); k += 2) frames.push_back(k);  // odd frames: the queries
    const size_t n = max_frames > 0 ? std::min(frames.size(), size_t(max_frames)) : frames.size();
    for (size_t i = 0; i < n; ++i)
    {
        const int k = frames[i * frames.size() / n];
        char name[32];
        std::snprintf(name, sizeof name, "%010d", k);
        const std::string path = dir + "/image_02/" + name + ".png";
        QueryFrame q;
        q.image = cv::imread(path, cv::IMREAD_COLOR);
        core::require(!q.image.empty(), path, "cannot read the image");
        q.name = std::string("kitti ") + name;
        q.T_world_cam = poses[size_t(k)];
        s.frames.push_back(std::move(q));
    }
    core::require(!s.frames.empty(), dir, "no query frame");
    s.camera = readCamera(dir + "/calib.txt", s.frames.front().image.size());
    return s;
}

}  // namespace quasiloc::bench
