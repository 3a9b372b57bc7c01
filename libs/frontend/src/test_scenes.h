#pragma once
// Synthetic inputs shared by the front-end unit tests (header only: not part of the library).
#include <mrpt/poses/CPose3D.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <quasiloc/core/camera_model.h>

namespace quasiloc::frontend::test
{
/** A deterministic textured 8-bit image: filled rectangles, circles and polygons of random gray levels over
 *  smooth noise (corners, blobs and straight edges for every detector). */
inline cv::Mat texturedImage(int width = 640, int height = 480, uint64_t seed = 7)
{
    cv::RNG rng(seed);
    cv::Mat noise(height / 8, width / 8, CV_8UC1);
    rng.fill(noise, cv::RNG::UNIFORM, 60, 190);
    cv::Mat img;
    cv::resize(noise, img, cv::Size(width, height), 0, 0, cv::INTER_CUBIC);
    for (int k = 0; k < 70; ++k)
    {
        const cv::Point c(rng.uniform(0, width), rng.uniform(0, height));
        const int s = rng.uniform(8, 60), g = rng.uniform(0, 256);
        switch (k % 3)
        {
            case 0: cv::rectangle(img, c, c + cv::Point(s, s * 2 / 3), cv::Scalar(g), cv::FILLED); break;
            case 1: cv::circle(img, c, s / 2, cv::Scalar(g), cv::FILLED, cv::LINE_AA); break;
            default:
            {
                std::vector<cv::Point> poly{c, c + cv::Point(s, s / 3), c + cv::Point(s / 2, s)};
                cv::fillConvexPoly(img, poly, cv::Scalar(g), cv::LINE_AA);
            }
        }
    }
    cv::GaussianBlur(img, img, cv::Size(3, 3), 0.7);
    return img;
}

/** Camera (z forward, x right, y down) at (x, y, z) with heading yaw about world z (world z up). */
inline mrpt::poses::CPose3D cameraPose(double x, double y, double z, double yaw, double pitch = 0.1)
{
    const mrpt::poses::CPose3D T_body_cam(0, 0, 0, -M_PI / 2, 0, -M_PI / 2);
    return mrpt::poses::CPose3D(x, y, z, yaw, pitch, 0.0) + T_body_cam;
}

inline core::CameraModel testCamera() { return core::CameraModel::pinhole(640, 480, 420, 420, 319.5, 239.5); }

}  // namespace quasiloc::frontend::test
