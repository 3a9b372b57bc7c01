#pragma once
// Point features behind one interface, the same for camera images and quasi-images (the paper's
// source-agnostic front-end): keypoints + descriptors + a dense descriptor map that the hybrid line
// descriptor samples along segments ("point branch", line_descriptor.h).
//
// Options: [Features] (FeatureOptions::declare, feature_options.cpp).
//
// Dense maps (point branch): XFeat: its `feats` output (64 channels, stride 8), L2-normalised per cell.
// Classical (orb, sift, akaze): a DAISY-like map computed at quarter resolution (stride 4): image gradients
// soft-binned into 8 unsigned orientations (magnitude-weighted), pooled by Gaussians of sigma 1 and 2 cells
// (4 and 8 image pixels; 16 channels), L2-normalised per cell. It describes the local gradient layout around a
// position, which is what a segment's neighbourhood looks like; it is not rotation invariant (neither is XFeat's).
#include <memory>
#include <opencv2/core.hpp>
#include <quasiloc/core/declared_options.h>
#include <string>
#include <utility>
#include <vector>

namespace quasiloc::frontend
{
enum class FeatureType
{
    Orb,
    Sift,
    Akaze,
    XFeat
};
/** The INI names of the feature types ([Features] type). */
const std::vector<std::pair<std::string, FeatureType>>& featureTypeNames();
std::string toString(FeatureType t);

/** A dense descriptor map: `data` is CV_32FC1 with rows = rows_cells * cols_cells and cols = channels
 *  (row y * cols_cells + x holds the vector of cell (x, y)); cell (x, y) is centred on image pixel
 *  (x * stride + offset, y * stride + offset). Vectors are L2-normalised. */
struct DenseMap
{
    cv::Mat data;
    int cols_cells = 0, rows_cells = 0;
    double stride = 1, offset = 0;

    bool empty() const { return data.empty(); }
    int channels() const { return data.cols; }
    /** Bilinear sample at image pixel (x, y) (clamped to the map), added with `weight` into out[0..channels). */
    void sampleAdd(float x, float y, float weight, float* out) const;
};

struct Features
{
    std::vector<cv::KeyPoint> keypoints;
    /** One row per keypoint: CV_8U (binary, Hamming) for ORB and AKAZE (MLDB), CV_32F L2-normalised for
     *  SIFT and XFeat. */
    cv::Mat descriptors;
    DenseMap dense;
    FeatureType type = FeatureType::Orb;
    /** The size of the image the keypoints come from (LighterGlue normalises keypoints by it); empty when the
     *  features were not made by an extractor. */
    cv::Size image_size;

    size_t size() const { return keypoints.size(); }
    bool binary() const { return descriptors.depth() == CV_8U; }
};

struct FeatureOptions : public core::DeclaredOptions
{
    FeatureType type = FeatureType::Orb;
    int max_keypoints = 1000;
    /** Spatial spreading: the image is cut into grid_cols x grid_rows cells; each cell keeps its strongest keypoints
     *  up to budget / cells, then the remaining budget goes to the strongest leftovers anywhere. */
    int grid_cols = 8, grid_rows = 6;
    double detect_factor = 2.0;
    int orb_fast_threshold = 12;  ///< camera images: lower than OpenCV's 20
    /** Quasi-images (given with a validity mask) have many weak FAST corners (rendering noise): why 20 and not 12,
     *  docs/experiments.md. */
    int orb_fast_threshold_masked = 20;
    int orb_levels = 6;
    double sift_contrast_threshold = 0.02;
    double akaze_threshold = 0.0005;
    std::string xfeat_model_path;
    double xfeat_detection_threshold = 0.05;
    bool dense_map = true;

    void declare(core::OptionTable& t) override;
    /** InputError naming `input` and the key for a value out of its declared range, or type = xfeat without a
     *  readable model file. */
    void check(const std::string& input) const;
};

class FeatureExtractor
{
   public:
    virtual ~FeatureExtractor() = default;
    /** Keypoints (at most max_keypoints, spread), descriptors and (if enabled) the dense map of an 8-bit
     *  grayscale image. `mask` (optional, CV_8UC1, same size): keypoints only where it is non-zero (a
     *  quasi-image's `valid`). InputError for an empty or non-8-bit-gray image. */
    virtual void extract(const cv::Mat& gray, const cv::Mat& mask, Features& out) = 0;
    virtual FeatureType type() const = 0;
};

/** Creates the extractor chosen by options (options.check() first). XFeat loads its model here. */
std::unique_ptr<FeatureExtractor> createFeatureExtractor(const FeatureOptions& options);

/** Keeps at most `budget` keypoints spread over a grid_cols x grid_rows grid of the image (see [Features]).
 *  Stable: among equal responses the earlier keypoint wins. */
std::vector<cv::KeyPoint> spreadKeypoints(const std::vector<cv::KeyPoint>& keypoints, cv::Size image_size, int budget,
                                          int grid_cols, int grid_rows);
/** spreadKeypoints as indices into `keypoints` (same selection, same order). */
std::vector<int> spreadKeypointIndices(const std::vector<cv::KeyPoint>& keypoints, cv::Size image_size, int budget,
                                       int grid_cols, int grid_rows);

/** Working images of computeGradientDenseMap, kept by a caller that computes one map per frame: reusing them
 *  spares a few MB of allocations per image, whose first-touch page faults cost more than the computation itself
 *  when the allocator has given the memory back to the system in between. */
struct DenseMapScratch
{
    cv::Mat half_u8, half, gx, gy, pooled;
    std::vector<cv::Mat> bins;
};

/** The classical dense map of [Features] (16 channels, stride 4). */
DenseMap computeGradientDenseMap(const cv::Mat& gray);
/** The same map, computed in `scratch` (the result does not depend on what scratch held before). */
DenseMap computeGradientDenseMap(const cv::Mat& gray, DenseMapScratch& scratch);

}  // namespace quasiloc::frontend
