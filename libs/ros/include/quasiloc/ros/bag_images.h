#pragma once
// sensor_msgs/Image and sensor_msgs/CompressedImage (messages.h, of ROS 1 and ROS 2 bags alike) <-> the 8-bit gray
// images quasiloc tracks on.
#include <opencv2/core.hpp>
#include <quasiloc/ros/messages.h>
#include <string>

namespace quasiloc::ros
{
/** A raw image as CV_8UC1: mono8 as is, mono16 shifted right by `mono16_shift_bits` (saturated), bgr8 / rgb8 /
 *  bgra8 / rgba8 converted to gray. Any other encoding, a wrong step or a short buffer is an InputError naming
 *  `where` (the topic and the time) and the encoding. */
cv::Mat grayFromImageMsg(const ImageMsg& msg, int mono16_shift_bits, const std::string& where);
/** A png or jpeg CompressedImage decoded to CV_8UC1 (color ones converted to gray). */
cv::Mat grayFromCompressedMsg(const CompressedImageMsg& msg, const std::string& where);

/** A CV_8UC1 image as a mono8 or mono16 Image message (step = width * bytes per pixel, little endian). */
ImageMsg imageMsgFromGray(const cv::Mat& gray, bool mono16);
/** A CV_8UC1 image as a png or jpeg CompressedImage message. */
CompressedImageMsg compressedMsgFromGray(const cv::Mat& gray, bool png, int jpeg_quality);

}  // namespace quasiloc::ros
