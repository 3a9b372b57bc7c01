#pragma once
// Appearance matching of a quasi-image to a camera image : the map's reflectivity and the camera's
// grey levels measure different things (laser return strength at 905 nm against visible radiance under the day's
// light), but where both see the same surfaces a monotone remapping can give the quasi-image the camera's grey-level
// distribution, which is what descriptors and detectors thresholds are tuned on.
#include <opencv2/core.hpp>
#include <quasiloc/quasi/quasi_image.h>

namespace quasiloc::quasi
{
/** An 8-bit image of q's reflectivity mapped through the monotone look-up table that gives its valid pixels the
 *  grey-level histogram of `camera_gray` (CV_8UC1, q's size) over those same pixels (the camera's view of the part
 *  of the scene the map covers, at q's pose); 0 where q is invalid. InputError for mismatched sizes or types. */
cv::Mat reflectivityMatchedToImage(const QuasiImage& q, const cv::Mat& camera_gray);

/** The look-up table alone: lut[b] is the camera grey level for reflectivity bin b of 256 over [0, 1]. */
std::vector<uint8_t> reflectivityToGrayTable(const cv::Mat& reflectivity, const cv::Mat& valid,
                                             const cv::Mat& camera_gray);

}  // namespace quasiloc::quasi
