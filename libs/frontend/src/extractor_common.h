#pragma once
// Helpers shared by the feature extractors (not part of the public interface).
#include <memory>
#include <opencv2/core.hpp>
#include <quasiloc/frontend/features.h>

namespace quasiloc::frontend::detail
{
/** InputError unless gray is non-empty CV_8UC1 and mask is empty or CV_8UC1 of the same size. */
void checkExtractorInput(const cv::Mat& gray, const cv::Mat& mask);
/** L2-normalises every row of a CV_32F matrix (zero rows stay zero). */
void normaliseRows(cv::Mat& m);
std::unique_ptr<FeatureExtractor> createXFeatExtractor(const FeatureOptions& options);
}  // namespace quasiloc::frontend::detail
