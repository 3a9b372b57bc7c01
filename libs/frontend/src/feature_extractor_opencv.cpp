// ORB, SIFT and AKAZE (OpenCV features2d) behind FeatureExtractor: detect detect_factor x budget candidates,
// spread them over the grid, then describe only the kept ones (describing is the expensive part for SIFT; ORB
// describes all candidates in its one pass, see extract).
#include <algorithm>
#include <opencv2/features2d.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/frontend/features.h>

#include "extractor_common.h"

namespace quasiloc::frontend
{
namespace
{
class OpenCvExtractor : public FeatureExtractor
{
   public:
    OpenCvExtractor(const FeatureOptions& o) : opt_(o), type_(o.type)
    {
        const int n = int(o.max_keypoints * o.detect_factor);
        switch (type_)
        {
            case FeatureType::Orb:
                orb_ =
                    cv::ORB::create(n, 1.2f, o.orb_levels, 19, 0, 2, cv::ORB::HARRIS_SCORE, 31, o.orb_fast_threshold);
                f2d_ = orb_;
                break;
            case FeatureType::Sift: f2d_ = cv::SIFT::create(n, 3, o.sift_contrast_threshold, 10, 1.6); break;
            case FeatureType::Akaze:
                f2d_ = cv::AKAZE::create(cv::AKAZE::DESCRIPTOR_MLDB, 0, 3, float(o.akaze_threshold), 4, 4);
                break;
            default: throw core::InputError("[Features] type", "not an OpenCV feature type");
        }
    }

    void extract(const cv::Mat& gray, const cv::Mat& mask, Features& out) override
    {
        detail::checkExtractorInput(gray, mask);
        std::vector<cv::KeyPoint> kps;
        if (type_ == FeatureType::Orb)
        {
            // ORB describes every candidate in the pass that detects them: compute() would build, border and blur
            // the image pyramid a second time (fresh buffers, so page faults too), which costs more than the
            // descriptors of the candidates spreading drops. The kept rows are what compute() gives for the kept
            // keypoints (feature_extractor_opencv_unittest checks it).
            // Quasi-images come with their validity mask, camera images without: each kind has its FAST threshold.
            orb_->setFastThreshold(mask.empty() ? opt_.orb_fast_threshold : opt_.orb_fast_threshold_masked);
            cv::Mat all;
            f2d_->detectAndCompute(gray, mask, kps, all);
            auto kept = spreadKeypointIndices(kps, gray.size(), opt_.max_keypoints, opt_.grid_cols, opt_.grid_rows);
            // compute() returns its keypoints grouped by pyramid level (stable): keep that order.
            std::stable_sort(kept.begin(), kept.end(),
                             [&](int a, int b) { return kps[size_t(a)].octave < kps[size_t(b)].octave; });
            out.keypoints.clear();
            out.descriptors = cv::Mat(int(kept.size()), all.cols, all.type());
            for (size_t k = 0; k < kept.size(); ++k)
            {
                out.keypoints.push_back(kps[size_t(kept[k])]);
                all.row(kept[k]).copyTo(out.descriptors.row(int(k)));
            }
        }
        else
        {
            // SIFT and AKAZE: describing is the expensive part, only the kept keypoints are.
            f2d_->detect(gray, kps, mask);
            out.keypoints = spreadKeypoints(kps, gray.size(), opt_.max_keypoints, opt_.grid_cols, opt_.grid_rows);
            f2d_->compute(gray, out.keypoints, out.descriptors);
        }
        if (out.descriptors.depth() == CV_32F) detail::normaliseRows(out.descriptors);
        out.type = type_;
        out.image_size = gray.size();
        out.dense = opt_.dense_map ? computeGradientDenseMap(gray, dense_scratch_) : DenseMap{};
    }
    FeatureType type() const override { return type_; }

   private:
    FeatureOptions opt_;
    FeatureType type_;
    cv::Ptr<cv::Feature2D> f2d_;
    cv::Ptr<cv::ORB> orb_;  ///< f2d_ when type = orb
    DenseMapScratch dense_scratch_;
};
}  // namespace

namespace detail
{
void checkExtractorInput(const cv::Mat& gray, const cv::Mat& mask)
{
    core::require(!gray.empty() && gray.type() == CV_8UC1, "feature extraction input",
                  "expected a non-empty 8-bit grayscale image (CV_8UC1)");
    core::require(mask.empty() || (mask.type() == CV_8UC1 && mask.size() == gray.size()), "feature extraction mask",
                  "expected an empty mask or a CV_8UC1 mask of the image's size");
}

void normaliseRows(cv::Mat& m)
{
    for (int r = 0; r < m.rows; ++r)
    {
        float* v = m.ptr<float>(r);
        double n2 = 0;
        for (int c = 0; c < m.cols; ++c) n2 += double(v[c]) * v[c];
        if (n2 <= 0) continue;
        const float inv = float(1.0 / std::sqrt(n2));
        for (int c = 0; c < m.cols; ++c) v[c] *= inv;
    }
}
}  // namespace detail

std::unique_ptr<FeatureExtractor> createFeatureExtractor(const FeatureOptions& options)
{
    options.check("feature options");
    if (options.type == FeatureType::XFeat) return detail::createXFeatExtractor(options);
    return std::make_unique<OpenCvExtractor>(options);
}
}  // namespace quasiloc::frontend
