// Image messages <-> 8-bit gray images (bag_images.h).
#include <algorithm>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/ros/bag_images.h>

using quasiloc::core::require;

namespace quasiloc::ros
{
namespace
{
cv::Mat view(const ImageMsg& msg, int type, int bytes_per_pixel, const std::string& where)
{
    require(msg.width > 0 && msg.height > 0, where, "image of size 0");
    require(
        msg.width <= 65535 && msg.height <= 65535, where,
        "image of " + std::to_string(msg.width) + "x" + std::to_string(msg.height) + " pixels (at most 65535 a side)");
    require(std::uint64_t(msg.step) >= std::uint64_t(msg.width) * std::uint64_t(bytes_per_pixel), where,
            "step " + std::to_string(msg.step) + " is less than width x " + std::to_string(bytes_per_pixel));
    require(msg.data.size() >= size_t(msg.step) * msg.height, where,
            "data holds " + std::to_string(msg.data.size()) + " bytes, step x height is " +
                std::to_string(size_t(msg.step) * msg.height));
    return cv::Mat(int(msg.height), int(msg.width), type, const_cast<uint8_t*>(msg.data.data()), msg.step);
}
}  // namespace

cv::Mat grayFromImageMsg(const ImageMsg& msg, int mono16_shift_bits, const std::string& where)
{
    const std::string& e = msg.encoding;
    cv::Mat gray;
    if (e == "mono8" || e == "8UC1")
        view(msg, CV_8UC1, 1, where).copyTo(gray);
    else if (e == "mono16" || e == "16UC1")
    {
        cv::Mat m16 = view(msg, CV_16UC1, 2, where).clone();
        if (msg.is_bigendian)
            for (int r = 0; r < m16.rows; ++r)
                for (auto* p = m16.ptr<uint16_t>(r); p != m16.ptr<uint16_t>(r) + m16.cols; ++p)
                    *p = uint16_t((*p >> 8) | (*p << 8));
        gray.create(m16.size(), CV_8UC1);  // a plain shift (no rounding), saturated
        for (int r = 0; r < m16.rows; ++r)
            for (int c = 0; c < m16.cols; ++c)
                gray.at<uint8_t>(r, c) = uint8_t(std::min(255, m16.at<uint16_t>(r, c) >> mono16_shift_bits));
    }
    else if (e == "bgr8")
        cv::cvtColor(view(msg, CV_8UC3, 3, where), gray, cv::COLOR_BGR2GRAY);
    else if (e == "rgb8")
        cv::cvtColor(view(msg, CV_8UC3, 3, where), gray, cv::COLOR_RGB2GRAY);
    else if (e == "bgra8")
        cv::cvtColor(view(msg, CV_8UC4, 4, where), gray, cv::COLOR_BGRA2GRAY);
    else if (e == "rgba8")
        cv::cvtColor(view(msg, CV_8UC4, 4, where), gray, cv::COLOR_RGBA2GRAY);
    else
        throw core::InputError(where, "image encoding '" + e +
                                          "' is not supported (mono8, mono16, bgr8, rgb8, bgra8, rgba8, or a "
                                          "png / jpeg sensor_msgs/CompressedImage)");
    return gray;
}

cv::Mat grayFromCompressedMsg(const CompressedImageMsg& msg, const std::string& where)
{
    const std::string format = msg.format;
    const bool png = format.find("png") != std::string::npos;
    const bool jpeg = format.find("jpeg") != std::string::npos || format.find("jpg") != std::string::npos;
    require(png || jpeg, where,
            "compressed image format '" + format + "' is not supported (png or jpeg; compressedDepth is not)");
    require(!msg.data.empty(), where, "compressed image with no data");
    cv::Mat img;
    try
    {
        img = cv::imdecode(msg.data, cv::IMREAD_UNCHANGED);
    }
    catch (const cv::Exception& e)
    {
        throw core::InputError(where, std::string("cannot decode the ") + (png ? "png" : "jpeg") + ": " + e.what());
    }
    require(!img.empty(), where, std::string("cannot decode the ") + (png ? "png" : "jpeg") + " data");
    if (img.depth() == CV_16U) img.convertTo(img, CV_8U, 1.0 / 256);
    require(img.depth() == CV_8U, where, "decoded image is neither 8- nor 16-bit");
    cv::Mat gray;
    if (img.channels() == 1)
        gray = img;
    else if (img.channels() == 3)
        cv::cvtColor(img, gray, cv::COLOR_BGR2GRAY);
    else if (img.channels() == 4)
        cv::cvtColor(img, gray, cv::COLOR_BGRA2GRAY);
    else
        throw core::InputError(where, "decoded image has " + std::to_string(img.channels()) + " channels");
    return gray;
}

ImageMsg imageMsgFromGray(const cv::Mat& gray, bool mono16)
{
    require(gray.type() == CV_8UC1 && !gray.empty(), "imageMsgFromGray", "expects a CV_8UC1 image");
    ImageMsg msg;
    msg.height = uint32_t(gray.rows);
    msg.width = uint32_t(gray.cols);
    msg.is_bigendian = false;
    msg.encoding = mono16 ? "mono16" : "mono8";
    msg.step = uint32_t(gray.cols * (mono16 ? 2 : 1));
    msg.data.resize(size_t(msg.step) * gray.rows);
    for (int r = 0; r < gray.rows; ++r)
    {
        const uint8_t* src = gray.ptr<uint8_t>(r);
        uint8_t* dst = msg.data.data() + size_t(r) * msg.step;
        if (!mono16)
            std::copy(src, src + gray.cols, dst);
        else
            for (int c = 0; c < gray.cols; ++c)
            {
                dst[2 * c] = 0;  // little endian: low byte first; value = 256 x gray
                dst[2 * c + 1] = src[c];
            }
    }
    return msg;
}

CompressedImageMsg compressedMsgFromGray(const cv::Mat& gray, bool png, int jpeg_quality)
{
    require(gray.type() == CV_8UC1 && !gray.empty(), "compressedMsgFromGray", "expects a CV_8UC1 image");
    CompressedImageMsg msg;
    msg.format = png ? "mono8; png compressed" : "mono8; jpeg compressed";
    const std::vector<int> params = png ? std::vector<int>{cv::IMWRITE_PNG_COMPRESSION, 1}
                                        : std::vector<int>{cv::IMWRITE_JPEG_QUALITY, jpeg_quality};
    std::vector<uchar> bytes;
    require(cv::imencode(png ? ".png" : ".jpg", gray, bytes, params), "compressedMsgFromGray", "encoding failed");
    msg.data.assign(bytes.begin(), bytes.end());
    return msg;
}

}  // namespace quasiloc::ros
