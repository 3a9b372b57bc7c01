#include "image_checks.h"

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <quasiloc/core/error.h>

namespace quasiloc::dataset::detail
{
std::string describeImage(const cv::Mat& img)
{
    return std::to_string(img.cols) + "x" + std::to_string(img.rows) + " " + cv::typeToString(img.type());
}

void requireGrayOfCameraSize(const cv::Mat& img, const core::CameraModel& cam, const std::string& input,
                             const std::string& camera_name)
{
    core::require(img.type() == CV_8UC1, input,
                  "image is " + describeImage(img) + ", expected 8-bit single-channel (grayscale)");
    core::require(img.cols == cam.width && img.rows == cam.height, input,
                  "image is " + describeImage(img) + " but the " + camera_name + " camera is " +
                      std::to_string(cam.width) + "x" + std::to_string(cam.height));
}

std::vector<unsigned char> readFileBytes(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    core::require(in.good() && std::filesystem::is_regular_file(path), path, "file not found or unreadable");
    in.seekg(0, std::ios::end);
    const auto size = static_cast<size_t>(in.tellg());
    in.seekg(0, std::ios::beg);
    std::vector<unsigned char> bytes(size);
    in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size));
    core::require(static_cast<size_t>(in.gcount()) == size, path, "read error");
    return bytes;
}

cv::Mat toGrayOfCameraSize(const cv::Mat& img, const core::CameraModel& cam, const std::string& input,
                           const std::string& camera_name)
{
    cv::Mat gray = img;
    // Rawlogs written by other MRPT tools may hold colour images; the estimator works on gray.
    if (img.type() == CV_8UC3)
        cv::cvtColor(img, gray, cv::COLOR_BGR2GRAY);
    else if (img.type() == CV_8UC4)
        cv::cvtColor(img, gray, cv::COLOR_BGRA2GRAY);
    requireGrayOfCameraSize(gray, cam, input, camera_name);
    return gray;
}

cv::Mat loadGrayImage(const std::string& path, const core::CameraModel& cam, const std::string& camera_name)
{
    core::require(std::filesystem::is_regular_file(path), path, "image file not found");
    const cv::Mat img = cv::imread(path, cv::IMREAD_UNCHANGED);
    core::require(!img.empty(), path, "cannot decode the image file");
    return toGrayOfCameraSize(img, cam, path, camera_name);
}

}  // namespace quasiloc::dataset::detail
