#pragma once
// Private helpers shared by the readers and the writer: decoding and checking stereo images.
#include <opencv2/core.hpp>
#include <quasiloc/core/camera_model.h>
#include <string>
#include <vector>

namespace quasiloc::dataset::detail
{
/** "752x480 8UC1". */
std::string describeImage(const cv::Mat& img);

/** Throws InputError(input, ...) unless img is CV_8UC1 of the camera's size. */
void requireGrayOfCameraSize(const cv::Mat& img, const core::CameraModel& cam, const std::string& input,
                             const std::string& camera_name);

/** Reads a whole file; InputError naming it when missing or unreadable. */
std::vector<unsigned char> readFileBytes(const std::string& path);

/** Decodes an image file for a FrameSource: grayscale as is, colour converted to gray, then the size
 *  checked against the camera. InputError naming the file otherwise. */
cv::Mat loadGrayImage(const std::string& path, const core::CameraModel& cam, const std::string& camera_name);

/** Same for an image already in memory (colour converted to gray); `input` names where it came from. */
cv::Mat toGrayOfCameraSize(const cv::Mat& img, const core::CameraModel& cam, const std::string& input,
                           const std::string& camera_name);

}  // namespace quasiloc::dataset::detail
