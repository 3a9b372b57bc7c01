#pragma once
// Synthetic descriptor "scenes" for the vocabulary's tests and benchmark: a pool of prototype descriptors (the
// scene's distinct structures); each image sees a random subset of them, every observation slightly noisy, so
// images share some words but not most.
#include <opencv2/core.hpp>
#include <random>
#include <vector>

namespace quasiloc::reloc::testing_support
{
struct DescriptorKind
{
    bool binary = true;
    int cols = 32;  // bytes (binary) or floats
};

inline cv::Mat randomDescriptors(const DescriptorKind& kind, int rows, std::mt19937& rng)
{
    if (kind.binary)
    {
        cv::Mat m(rows, kind.cols, CV_8U);
        for (int r = 0; r < rows; ++r)
            for (int c = 0; c < kind.cols; ++c) m.at<uint8_t>(r, c) = uint8_t(rng() & 0xFF);
        return m;
    }
    std::normal_distribution<float> gauss;
    cv::Mat m(rows, kind.cols, CV_32F);
    for (int r = 0; r < rows; ++r)
    {
        for (int c = 0; c < kind.cols; ++c) m.at<float>(r, c) = gauss(rng);
        cv::normalize(m.row(r), m.row(r));  // unit vectors, like SIFT-style normalised descriptors
    }
    return m;
}

/** A noisy observation of a prototype row: a few flipped bits, or a small Gaussian perturbation. */
inline void observe(const cv::Mat& prototype, cv::Mat out_row, std::mt19937& rng)
{
    prototype.copyTo(out_row);
    if (prototype.type() == CV_8U)
    {
        for (int flip = 0; flip < 6; ++flip)
        {
            const int bit = int(rng() % (8 * prototype.cols));
            out_row.at<uint8_t>(0, bit / 8) ^= uint8_t(1 << (bit % 8));
        }
        return;
    }
    std::normal_distribution<float> gauss(0.f, 0.03f);
    for (int c = 0; c < prototype.cols; ++c) out_row.at<float>(0, c) += gauss(rng);
    cv::normalize(out_row, out_row);
}

inline std::vector<cv::Mat> sceneImages(const DescriptorKind& kind, int images, int per_image, int prototypes,
                                        unsigned seed)
{
    std::mt19937 rng(seed);
    const cv::Mat pool = randomDescriptors(kind, prototypes, rng);
    std::vector<cv::Mat> out;
    for (int i = 0; i < images; ++i)
    {
        cv::Mat m(per_image, kind.cols, pool.type());
        for (int r = 0; r < per_image; ++r) observe(pool.row(int(rng() % prototypes)), m.row(r), rng);
        out.push_back(m);
    }
    return out;
}

}  // namespace quasiloc::reloc::testing_support
