#pragma once
// Decoding a JPEG embedded in a rawlog (an mrpt::img::CImage stored as JPEG) without MRPT: MRPT's decoder uses
// libjpeg's default error handler, which calls exit(1) on corrupt data. OpenCV's decoder reports the error instead.
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace quasiloc::dataset::detail
{
struct JpegFrameSize
{
    int width = 0, height = 0, components = 0;
};

/** Width, height and component count from the JPEG's frame header (SOFn), found by walking the marker segments
 *  from the start. InputError naming `input` when the bytes are no JPEG or end before a frame header. */
JpegFrameSize readJpegFrameSize(const std::vector<std::uint8_t>& jpeg, const std::string& input);

/** Decodes as MRPT's CImage::loadFromStreamAsJPEG does: 1 component -> 8UC1, 3 -> 8UC3 BGR. The frame header is
 *  checked first (1 or 3 components, at most `max_pixels`), so that a small corrupt file cannot make the decoder
 *  allocate gigabytes; a corrupt file is an InputError naming `input`, never exit(). */
cv::Mat decodeEmbeddedJpeg(const std::vector<std::uint8_t>& jpeg, const std::string& input, std::uint64_t max_pixels);

}  // namespace quasiloc::dataset::detail
