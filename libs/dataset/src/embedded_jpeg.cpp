#include "embedded_jpeg.h"

#include <opencv2/imgcodecs.hpp>
#include <quasiloc/core/error.h>

namespace quasiloc::dataset::detail
{
JpegFrameSize readJpegFrameSize(const std::vector<std::uint8_t>& b, const std::string& input)
{
    using core::require;
    require(b.size() >= 4 && b[0] == 0xFF && b[1] == 0xD8, input, "embedded JPEG does not start with SOI (FF D8)");
    size_t at = 2;
    for (;;)
    {
        // A marker: one or more 0xFF fill bytes, then the marker code.
        require(at < b.size() && b[at] == 0xFF, input, "embedded JPEG: no marker where one is expected");
        while (at < b.size() && b[at] == 0xFF) ++at;
        require(at < b.size(), input, "embedded JPEG ends before its frame header");
        const std::uint8_t marker = b[at++];
        if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) continue;  // no length field
        require(marker != 0xD9 && marker != 0xDA, input, "embedded JPEG has no frame header before its scan");
        require(at + 2 <= b.size(), input, "embedded JPEG ends inside a marker segment");
        const size_t length = (size_t(b[at]) << 8) | b[at + 1];
        require(length >= 2 && at + length <= b.size(), input, "embedded JPEG: a marker segment beyond its end");
        // SOF0..SOF15, except DHT (C4), JPG (C8) and DAC (CC): precision, height, width, components.
        if (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC)
        {
            require(length >= 8, input, "embedded JPEG: frame header too short");
            JpegFrameSize s;
            s.height = (int(b[at + 3]) << 8) | b[at + 4];
            s.width = (int(b[at + 5]) << 8) | b[at + 6];
            s.components = b[at + 7];
            return s;
        }
        at += length;
    }
}

cv::Mat decodeEmbeddedJpeg(const std::vector<std::uint8_t>& jpeg, const std::string& input, std::uint64_t max_pixels)
{
    using core::require;
    const JpegFrameSize s = readJpegFrameSize(jpeg, input);
    const std::string size = std::to_string(s.width) + "x" + std::to_string(s.height);
    require(s.width > 0 && s.height > 0, input,
            "embedded JPEG of size " + size +
                " (corrupt, or its height in a DNL "
                "marker, which this reader does not support)");
    require(std::uint64_t(s.width) * std::uint64_t(s.height) <= max_pixels, input,
            "embedded JPEG of " + size + " pixels is beyond this reader's " + std::to_string(max_pixels));
    require(s.components == 1 || s.components == 3, input,
            "embedded JPEG with " + std::to_string(s.components) + " components (gray or YCbCr colour expected)");
    cv::Mat img;
    try
    {
        img = cv::imdecode(jpeg, cv::IMREAD_UNCHANGED);
    }
    catch (const cv::Exception& e)
    {
        throw core::InputError(input, std::string("cannot decode the embedded JPEG: ") + e.what());
    }
    require(!img.empty(), input, "cannot decode the embedded JPEG (corrupt data)");
    require(img.cols == s.width && img.rows == s.height && img.channels() == s.components, input,
            "the embedded JPEG decodes to " + std::to_string(img.cols) + "x" + std::to_string(img.rows) + " with " +
                std::to_string(img.channels()) + " channels, its frame header says " + size);
    return img;
}

}  // namespace quasiloc::dataset::detail
