// XFeat (Potje et al., CVPR 2024) through OpenCV DNN: the ONNX backbone's three outputs (see
// ../shared/models/README.md) turned into keypoints, descriptors and the dense map. The model is optional: it
// is loaded only when [Features] type = xfeat, from [Features] xfeat_model_path.
#include <algorithm>
#include <cmath>
#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/frontend/features.h>

#include "extractor_common.h"

namespace quasiloc::frontend
{
namespace
{
constexpr int kCell = 8;

class XFeatExtractor : public FeatureExtractor
{
   public:
    explicit XFeatExtractor(const FeatureOptions& o) : opt_(o)
    {
        try
        {
            net_ = cv::dnn::readNetFromONNX(o.xfeat_model_path);
        }
        catch (const cv::Exception& e)
        {
            throw core::InputError(o.xfeat_model_path, std::string("cannot load the XFeat ONNX model: ") + e.what());
        }
        core::require(!net_.empty(), o.xfeat_model_path, "the XFeat ONNX model is empty");
        out_names_ = net_.getUnconnectedOutLayersNames();
        core::require(out_names_.size() == 3, o.xfeat_model_path,
                      "expected 3 outputs (feats, keypoints, heatmap), found " + std::to_string(out_names_.size()));
    }

    FeatureType type() const override { return FeatureType::XFeat; }

    void extract(const cv::Mat& gray, const cv::Mat& mask, Features& out) override
    {
        detail::checkExtractorInput(gray, mask);
        cv::Mat feats, logits, reliability;
        forward(gray, feats, logits, reliability);
        const int h = feats.size[2], w = feats.size[3];

        out.dense = denseFromFeats(feats, h, w);
        const cv::Mat prob = keypointProbability(logits, h, w);
        std::vector<cv::KeyPoint> kps = nmsKeypoints(prob, mask, gray.size());
        const DenseMap rel = singleChannelMap(reliability, h, w);
        for (auto& k : kps)
        {
            float r = 0;
            rel.sampleAdd(k.pt.x, k.pt.y, 1.f, &r);
            k.response *= r;
        }
        out.keypoints = spreadKeypoints(kps, gray.size(), opt_.max_keypoints, opt_.grid_cols, opt_.grid_rows);
        out.descriptors = cv::Mat::zeros(int(out.keypoints.size()), out.dense.channels(), CV_32F);
        for (size_t i = 0; i < out.keypoints.size(); ++i)
            out.dense.sampleAdd(out.keypoints[i].pt.x, out.keypoints[i].pt.y, 1.f, out.descriptors.ptr<float>(int(i)));
        detail::normaliseRows(out.descriptors);
        out.type = FeatureType::XFeat;
        out.image_size = gray.size();  // the original size, not the padded one (LighterGlue normalises by it)
        if (!opt_.dense_map) out.dense = DenseMap{};
    }

   private:
    /** Pads to multiples of 32 (replicating the border: no resampling, so keypoints need no rescaling). */
    void forward(const cv::Mat& gray, cv::Mat& feats, cv::Mat& logits, cv::Mat& reliability)
    {
        const int W = (gray.cols + 31) / 32 * 32, H = (gray.rows + 31) / 32 * 32;
        cv::Mat padded;
        cv::copyMakeBorder(gray, padded, 0, H - gray.rows, 0, W - gray.cols, cv::BORDER_REPLICATE);
        net_.setInput(cv::dnn::blobFromImage(padded, 1.0 / 255.0), "image");
        std::vector<cv::Mat> outs;
        net_.forward(outs, out_names_);
        for (auto& o : outs)
        {
            core::require(o.dims == 4, opt_.xfeat_model_path, "unexpected output rank");
            if (o.size[1] == 64)
                feats = o;
            else if (o.size[1] == 65)
                logits = o;
            else if (o.size[1] == 1)
                reliability = o;
        }
        core::require(!feats.empty() && !logits.empty() && !reliability.empty(), opt_.xfeat_model_path,
                      "outputs are not feats (64 ch), keypoints (65 ch) and heatmap (1 ch)");
    }

    /** feats (1x64xhxw) -> per-cell L2-normalised DenseMap, cell (x, y) centred on pixel 8x + 3.5. */
    static DenseMap denseFromFeats(const cv::Mat& feats, int h, int w)
    {
        const int C = feats.size[1];
        DenseMap m;
        m.cols_cells = w, m.rows_cells = h, m.stride = kCell, m.offset = 0.5 * kCell - 0.5;
        cv::Mat planes(C, h * w, CV_32F, const_cast<float*>(feats.ptr<float>()));
        cv::transpose(planes, m.data);
        detail::normaliseRows(m.data);
        return m;
    }

    static DenseMap singleChannelMap(const cv::Mat& rel, int h, int w)
    {
        DenseMap m;
        m.cols_cells = w, m.rows_cells = h, m.stride = kCell, m.offset = 0.5 * kCell - 0.5;
        m.data = cv::Mat(h * w, 1, CV_32F, const_cast<float*>(rel.ptr<float>())).clone();
        return m;
    }

    /** Softmax over the 65 channels per cell, dustbin dropped, pixel shuffle (cell row-major) -> HxW. */
    static cv::Mat keypointProbability(const cv::Mat& logits, int h, int w)
    {
        const int C = logits.size[1];
        const float* L = logits.ptr<float>();
        const size_t plane = size_t(h) * w;
        cv::Mat prob(h * kCell, w * kCell, CV_32F);
        std::vector<float> e(C);
        for (int cy = 0; cy < h; ++cy)
            for (int cx = 0; cx < w; ++cx)
            {
                const size_t off = size_t(cy) * w + cx;
                float mx = -1e30f;
                for (int c = 0; c < C; ++c) mx = std::max(mx, L[c * plane + off]);
                float sum = 0;
                for (int c = 0; c < C; ++c) sum += (e[c] = std::exp(L[c * plane + off] - mx));
                for (int c = 0; c < kCell * kCell; ++c)
                    prob.at<float>(cy * kCell + c / kCell, cx * kCell + c % kCell) = e[c] / sum;
            }
        return prob;
    }

    /** Local maxima of a 5x5 window above the threshold, inside the original image and the mask. */
    std::vector<cv::KeyPoint> nmsKeypoints(const cv::Mat& prob, const cv::Mat& mask, cv::Size image) const
    {
        cv::Mat dil;
        cv::dilate(prob, dil, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(5, 5)));
        std::vector<cv::KeyPoint> kps;
        const float thr = float(opt_.xfeat_detection_threshold);
        for (int y = 0; y < image.height; ++y)
        {
            const float* p = prob.ptr<float>(y);
            const float* d = dil.ptr<float>(y);
            const uchar* mk = mask.empty() ? nullptr : mask.ptr<uchar>(y);
            for (int x = 0; x < image.width; ++x)
                if (p[x] > thr && p[x] >= d[x] && (!mk || mk[x]))
                    kps.emplace_back(cv::Point2f(float(x), float(y)), float(kCell), -1.f, p[x], 0);
        }
        return kps;
    }

    FeatureOptions opt_;
    cv::dnn::Net net_;
    std::vector<std::string> out_names_;
};
}  // namespace

namespace detail
{
std::unique_ptr<FeatureExtractor> createXFeatExtractor(const FeatureOptions& options)
{
    return std::make_unique<XFeatExtractor>(options);
}
}  // namespace detail
}  // namespace quasiloc::frontend
