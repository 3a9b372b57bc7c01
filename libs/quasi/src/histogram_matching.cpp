// Histogram matching of the quasi-image's reflectivity to a camera image (histogram_matching.h).
#include <quasiloc/quasi/histogram_matching.h>

#include <algorithm>
#include <array>
#include <quasiloc/core/error.h>

namespace quasiloc::quasi
{
namespace
{
int reflectivityBin(float r) { return std::clamp(int(r * 256.f), 0, 255); }
}  // namespace

std::vector<uint8_t> reflectivityToGrayTable(const cv::Mat& reflectivity, const cv::Mat& valid,
                                             const cv::Mat& camera_gray)
{
    const std::string in = "reflectivity histogram matching";
    core::require(reflectivity.type() == CV_32FC1 && valid.type() == CV_8UC1 && camera_gray.type() == CV_8UC1, in,
                  "needs CV_32FC1 reflectivity, CV_8UC1 validity and a CV_8UC1 camera image");
    core::require(reflectivity.size() == valid.size() && camera_gray.size() == valid.size(), in,
                  "the camera image and the quasi-image differ in size");
    std::array<double, 256> refl{}, gray{};
    for (int y = 0; y < valid.rows; ++y)
    {
        const uint8_t* v = valid.ptr<uint8_t>(y);
        const float* r = reflectivity.ptr<float>(y);
        const uint8_t* g = camera_gray.ptr<uint8_t>(y);
        for (int x = 0; x < valid.cols; ++x)
            if (v[x]) ++refl[size_t(reflectivityBin(r[x]))], ++gray[g[x]];
    }
    // Cumulative distributions; each reflectivity bin takes the first grey level whose share reaches the share of
    // pixels at or below the bin's centre.
    std::vector<uint8_t> lut(256, 0);
    double total = 0;
    for (double c : refl) total += c;
    if (total == 0) return lut;
    for (size_t i = 1; i < 256; ++i) refl[i] += refl[i - 1], gray[i] += gray[i - 1];
    size_t g = 0;
    for (size_t b = 0; b < 256; ++b)
    {
        const double share = (refl[b] - 0.5 * (refl[b] - (b ? refl[b - 1] : 0))) / total;
        while (g < 255 && gray[g] / total < share) ++g;
        lut[b] = uint8_t(g);
    }
    return lut;
}

cv::Mat reflectivityMatchedToImage(const QuasiImage& q, const cv::Mat& camera_gray)
{
    const std::vector<uint8_t> lut = reflectivityToGrayTable(q.reflectivity, q.valid, camera_gray);
    cv::Mat out = cv::Mat::zeros(q.valid.size(), CV_8UC1);
    for (int y = 0; y < out.rows; ++y)
    {
        const uint8_t* v = q.valid.ptr<uint8_t>(y);
        const float* r = q.reflectivity.ptr<float>(y);
        uint8_t* o = out.ptr<uint8_t>(y);
        for (int x = 0; x < out.cols; ++x)
            if (v[x]) o[x] = lut[size_t(reflectivityBin(r[x]))];
    }
    return out;
}

}  // namespace quasiloc::quasi
