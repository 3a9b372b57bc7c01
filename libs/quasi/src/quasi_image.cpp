// What a quasi-image offers its keypoints (quasi_image.h).
#include <opencv2/imgproc.hpp>
#include <quasiloc/quasi/quasi_image.h>

namespace quasiloc::quasi
{
cv::Mat keypointSupportMask(const QuasiImage& q, int margin, double min_valid_share)
{
    cv::Mat mask = cv::Mat::zeros(q.valid.size(), CV_8U);
    if (q.valid.cols <= 2 * margin || q.valid.rows <= 2 * margin) return mask;
    cv::Mat valid01, share;
    cv::Mat(q.valid != 0).convertTo(valid01, CV_32F, 1.0 / 255.0);
    cv::boxFilter(valid01, share, CV_32F, cv::Size(2 * margin + 1, 2 * margin + 1));
    const cv::Rect inside(margin, margin, mask.cols - 2 * margin, mask.rows - 2 * margin);
    mask(inside).setTo(255);
    mask &= (share >= min_valid_share) & (q.sparse != 0) & (q.provenance >= 0);
    return mask;
}
}  // namespace quasiloc::quasi
