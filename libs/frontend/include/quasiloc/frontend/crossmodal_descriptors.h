#pragma once
// Dense descriptors for matching a camera image against a LiDAR quasi-image, whose intensities are unrelated or
// inverted point by point (docs/crossmodal_statistics.md: on KITTI the grey level and the reflectivity have a rank
// correlation of zero; what the two share is gradient orientation with the sign ignored, on the depth channel as
// much as on the reflectivity). docs/crossmodal_matching.md measures which combination finds the most correct
// correspondences.
//
// Channels (every result CV_32FC1, the input's size):
//  - locallyNormalised: the camera image minus its local mean over its local standard deviation (Gaussian window),
//    so that shade and exposure differences across the image weigh less;
//  - rankEqualised: the quasi-image's reflectivity replaced by its rank among the valid pixels of its range band
//    (log-depth bands): the LiDAR's range falloff and uncalibrated gains shift levels per range, ranks do not care;
//  - depthEdgeChannel: log depth minus its local mean (Gaussian, over valid pixels), compressed by tanh: occlusion
//    boundaries (steps) and creases (normal changes) stay, planes and the perspective ramp of the ground vanish;
//  - fillInvalid: invalid pixels of a quasi-image channel filled from their valid neighbours (normalised
//    convolution), so that a hole does not draw an edge that the camera image does not have.
//
// Descriptors, sampled from a DescriptorField (per-pixel channels read at fixed offsets around the point):
//  - Ncc: the smoothed patch, zero mean and unit norm: L2 distance^2 = 2 - 2 NCC. The baseline: it assumes a
//    positive linear relation of intensities;
//  - Mind: MIND-SSC (Heinrich et al., MICCAI 2013) in 2D: for the six pairs of the four neighbours at distance r
//    (the four adjacent pairs and the two opposite ones), the Gaussian-weighted squared patch difference D_k(x);
//    MIND_k = exp(-(D_k - min_k D_k) / V(x)), V = mean_k D_k (the local variance estimate, clamped to
//    [1e-3, 1e3] x its image mean). The same for an image and its inversion (the differences are squared); read
//    on a grid of mind_grid x mind_grid points mind_step apart around the point;
//  - OrientationField: gradient orientations modulo 180 deg (sign ignored) soft-binned into orientation_bins,
//    each pixel's vote its magnitude over the local RMS magnitude (magnitudes are not shared across the gap,
//    their local layout is), pooled over cells of orientation_cell_px, orientation_cells x orientation_cells
//    cells around the point; the vector L2-normalised, clipped at orientation_clip and renormalised (as SIFT).
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace quasiloc::frontend
{
/** (I - mean) / max(std, min_std) over a Gaussian window of sigma_px; input 8-bit or float gray; min_std in the
 *  input's units. */
cv::Mat locallyNormalised(const cv::Mat& gray, double sigma_px, double min_std);

/** Rank of each valid pixel's value among the valid pixels of its band, scaled to [0, 1] (ties share their mean
 *  rank); 0 where invalid. With depth (CV_32F, metres) and depth_bands > 1 the valid depths are cut into
 *  depth_bands bands of equal log-depth width; otherwise one band. `valid`: CV_8U, non-zero = valid. */
cv::Mat rankEqualised(const cv::Mat& values, const cv::Mat& valid, const cv::Mat& depth = cv::Mat(),
                      int depth_bands = 1);

/** tanh((log D - local mean of log D) / scale), the mean a Gaussian of sigma_px over the valid pixels; 0 where
 *  invalid. depth: CV_32F metres (<= 0: invalid as well). */
cv::Mat depthEdgeChannel(const cv::Mat& depth, const cv::Mat& valid, double sigma_px, double scale);

/** Invalid pixels take the Gaussian-weighted mean (sigma_px) of the valid ones; those with no valid pixel nearby
 *  the mean of all valid pixels. Valid pixels keep their value. */
cv::Mat fillInvalid(const cv::Mat& values, const cv::Mat& valid, double sigma_px);

enum class DescriptorKind
{
    Ncc,
    Mind,
    OrientationField
};
std::string toString(DescriptorKind k);

struct CrossModalDescriptorOptions
{
    double smooth_sigma_px = 1.0;  ///< Gaussian smoothing before every descriptor
    int ncc_radius_px = 5;         ///< NCC patch: (2 r + 1)^2 pixels
    int mind_distance_px = 2;      ///< MIND-SSC: neighbour distance r
    double mind_patch_sigma_px = 1.0;
    int mind_grid = 5;     ///< MIND read at mind_grid x mind_grid points ...
    int mind_step_px = 2;  ///< ... this far apart
    int orientation_bins = 8;
    int orientation_cell_px = 5;
    int orientation_cells = 4;
    double orientation_norm_sigma_px = 8;  ///< the local RMS magnitude's Gaussian window
    double orientation_clip = 0.2;
};

/** Per-pixel channels and the offsets a descriptor reads them at: descriptor of (x, y) =
 *  [channels[c](y + o.y, x + o.x) for o in offsets for c in channels], then normalised by kind. */
class DescriptorField
{
   public:
    DescriptorKind kind = DescriptorKind::Ncc;
    std::vector<cv::Mat> channels;  ///< CV_32FC1, all the image's size
    std::vector<cv::Point> offsets;
    double clip = 0.2;  ///< OrientationField: SIFT-like clipping

    int dims() const { return int(channels.size() * offsets.size()); }
    /** The largest |offset| component: describe() needs this margin inside the image. */
    int radius() const;
    cv::Size size() const { return channels.empty() ? cv::Size() : channels.front().size(); }
    bool inside(int x, int y) const;
    /** Writes the normalised descriptor of pixel (x, y) to out[0..dims()); false (out untouched) when the footprint
     *  leaves the image or the descriptor has no contrast. */
    bool describe(int x, int y, float* out) const;
};

/** The descriptor field of a gray image (CV_8U or CV_32F; the values' scale does not matter). */
DescriptorField computeDescriptorField(const cv::Mat& image, DescriptorKind kind,
                                       const CrossModalDescriptorOptions& options);

/** Squared L2 distance of two descriptors of n values. */
float squaredDistance(const float* a, const float* b, int n);

}  // namespace quasiloc::frontend
