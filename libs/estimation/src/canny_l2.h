#pragma once
// Canny edges from given derivatives with the L2 gradient norm: the edges cv::Canny(dx, dy, edges, low, high, true)
// gives, bit for bit, at about half its CPU time. The camera edge field runs it on every pyramid level of every
// frame, with about a fifth of the pixels ending up as edges: there OpenCV's scalar non-maximum suppression, its
// branches mispredicting on such images, was the largest single cost of the tracking thread.
#include <opencv2/core/mat.hpp>

namespace quasiloc::estimation::detail
{
/** `dx`, `dy`: CV_16SC1 derivatives of one size, |dx| < 27146 (any 3x3 or 5x5 Sobel of an 8-bit image; OpenCV's
 *  integer arithmetic overflows beyond, and so would this). Thresholds as cv::Canny's on the gradient norm
 *  (swapped when low > high). `edges`: CV_8UC1, 255 on the edges, 0 elsewhere. The result is OpenCV's: a pixel is a
 *  candidate when its squared norm exceeds floor(low^2) and is a maximum along its quantised gradient direction
 *  (OpenCV's fixed-point tangent tests and its strict and non-strict comparisons), and an edge when it is
 *  8-connected through candidates to one whose squared norm exceeds floor(high^2). InputError for other types or
 *  sizes. `avx2`: eight pixels per instruction where the CPU has AVX2, else four (false: four; the tests check
 *  both). */
void cannyL2(const cv::Mat& dx, const cv::Mat& dy, double low, double high, cv::Mat& edges, bool avx2 = true);
}  // namespace quasiloc::estimation::detail
