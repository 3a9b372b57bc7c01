#pragma once
// Direct camera-to-map alignment: a term that needs no descriptor to agree across the camera/LiDAR modality
// gap (beyond the paper). Two measures of how well the map, seen at a pose, lines up with the image:
//
//  * EDGES (the optimised term). Map edges are the quasi-image's depth discontinuities (near side: the
//    occluding contour) and reflectivity edges (Canny on the completed reflectivity, e.g. lane markings),
//    lifted to 3D with the completed depth along the pixel ray. Camera edges are Canny edges of the image;
//    their truncated Euclidean distance transform DT is the residual field: r_i = DT(pi(T_cam_world P_i)).
//    Both modalities show object boundaries at the same place even when their intensities disagree, which
//    is why this crosses the gap where descriptors fail. Minimised by Levenberg-Marquardt (Huber weights) on
//    an image pyramid, coarse to fine: the coarse levels' distance fields are smooth over tens of pixels,
//    which gives the basin of attraction; the fine level gives the precision.
//  * NMI (a measure, not optimised: bench_crossmodal's cost profile). Normalised mutual information (Studholme)
//    between the camera intensity at the projection of map points and their reflectivity (Wolcott & Eustice,
//    IROS 2014): it rewards any consistent (not necessarily linear) relation between the two. Computed from a
//    joint histogram.
//
// The model (map side) is built from one quasi-image rendered at the initial pose; the camera side once per
// image. Poses: T_world_cam maps camera coordinates to world; updates are right perturbations in the camera
// frame, delta = [dtheta; dp] (pose_parametrization.h).
//
// Options: [DirectAlignment], declared in DirectAlignmentOptions::declare (direct_alignment_options.cpp).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/core/declared_options.h>
#include <string>
#include <vector>

namespace quasiloc::estimation
{
struct DirectAlignmentOptions : public core::DeclaredOptions
{
    int pyramid_levels = 2;
    double camera_blur_sigma_px = 0;
    double canny_high_percentile = 85;
    double canny_low_ratio = 0.4;
    /** Directional chamfer: a map edge is attracted only by camera edges within 180/bins deg of its own
     *  orientation. Up to 8 classes share one fused distance transform (classDistanceTransforms), so the camera
     *  side costs about one transform per level whatever the bins. Why 6: docs/experiments.md. */
    int orientation_bins = 6;
    double truncation_px = 12;
    double huber_px = 2;
    int iterations_per_level = 12;
    int max_edge_points = 3000;
    int model_block_px = 4;
    int model_close_px = 2;
    double depth_edge_rel = 0.08;
    double refl_canny_high = 0.12;
    bool use_reflectivity_edges = true;
    int nmi_bins = 24;
    int max_nmi_points = 6000;

    void declare(core::OptionTable& t) override;
};

/** The map side: 3D points (world frame) on map edges. */
struct DirectAlignmentModel
{
    std::vector<Eigen::Vector3d> edge_points_world;
    std::vector<uint8_t> edge_bin;  ///< orientation class of each edge point (its image normal at the model pose)
};

/** Builds the model from a quasi-image's completed depth, reflectivity, validity and sparse masks, rendered
 *  with `camera` at T_world_cam (any renderer: only the planes are read). Edge points are lifted along the
 *  pixel ray with the completed depth. `downscale`: the planes were rendered at 1/downscale of the tracked
 *  camera's resolution (`camera` is the downscaled one); the blocks are model_block_px / downscale of their
 *  pixels, which it must divide, so that the model is found on the same image blocks. Deterministic. */
DirectAlignmentModel buildDirectAlignmentModel(const DirectAlignmentOptions& options, const cv::Mat& depth,
                                               const cv::Mat& reflectivity, const cv::Mat& valid, const cv::Mat& sparse,
                                               const core::CameraModel& camera, const Eigen::Isometry3d& T_world_cam,
                                               int downscale = 1);

/** Map points with reflectivity for the NMI measure: sparse pixels (exact map points) of a quasi-image rendered
 *  at T_world_cam, at most max_nmi_points spread over the image. Kept apart from the edge model because no stage
 *  of the tracker uses NMI (docs/experiments.md): the tracker does not pay for it. */
struct NmiSamples
{
    std::vector<Eigen::Vector3d> points_world;
    std::vector<float> reflectivity;  ///< [0, 1], one per point
};
NmiSamples buildNmiSamples(const DirectAlignmentOptions& options, const cv::Mat& depth, const cv::Mat& reflectivity,
                           const cv::Mat& sparse, const core::CameraModel& camera,
                           const Eigen::Isometry3d& T_world_cam);

/** Orientation classes of image normal directions (gx, gy): the angle mod 180 deg in `bins` classes centred on
 *  multiples of 180 / bins deg. */
class OrientationClasses
{
   public:
    explicit OrientationClasses(int bins);
    /** The class of (gx, gy); `second` (optional) = the neighbouring class on the side the angle leans to. */
    int classOf(float gx, float gy, int* second = nullptr) const;
    /** For n gradients (bins <= 8): bits[i] = (1 << class) | (1 << second) of (gx[i], gy[i]), the classes classOf
     *  gives, four gradients at a time (the camera edge field's tens of thousands of edge pixels per image).
     *  InputError for more than 8 bins. */
    void pairBits(const float* gx, const float* gy, size_t n, uint8_t* bits) const;

   private:
    /** The sector of (gx, gy) in [0, 2 * bins): between a class centre and a class border (classOf). */
    int sectorOf(float gx, float gy) const;
    /** The class of a sector, and its neighbour on the side the sector leans to. */
    int classOfSector(int sector, int* second) const;

    int bins_;
    std::vector<float> cos_, sin_;      ///< the sector borders up to 90 deg: k * 90 / bins deg, k = 1 .. bins
    std::vector<uint8_t> sector_bits_;  ///< per sector (2 * bins of them, bins <= 8): the bits pairBits gives
};

/** One pyramid level of the camera side. */
struct CameraEdgeLevel
{
    double scale = 1;  ///< level pixel = (full pixel + 0.5) * scale - 0.5
    /** Per orientation class: CV_32F truncated distance to the nearest Canny edge of that class (level pixels;
     *  its gradient is taken by central differences where needed). A camera edge belongs to the two classes
     *  nearest to its orientation. */
    std::vector<cv::Mat> distance;
    cv::Mat edges;  ///< CV_8U Canny edges (255)
};

/** The camera side, computed once per image. */
struct CameraEdgeField
{
    std::vector<CameraEdgeLevel> levels;  ///< [0] = full resolution
    cv::Mat gray;                         ///< the image, lightly smoothed (NMI samples it)
};

/** Up to this many orientation classes share one fused distance transform (classDistanceTransforms). */
constexpr int kMaxFusedClasses = 8;

/** The truncated distance transforms of up to 8 pixel classes in one pass: `class_bits` (CV_8UC1) has bit k set
 *  at the pixels of class k; distance[k] (CV_32F, same size) = min(distance to the nearest pixel of class k,
 *  truncation_px), with cv::distanceTransform's DIST_L2 / DIST_MASK_3 chamfer metric (weights to ~1e-4 px per
 *  step: the same field within rounding). A class with no pixel gets truncation_px everywhere. InputError for an
 *  empty or non-CV_8UC1 image, classes outside [1, 8], truncation_px outside [1, 1000]. */
void classDistanceTransforms(const cv::Mat& class_bits, int classes, double truncation_px,
                             std::vector<cv::Mat>& distance);

/** InputError for an empty or non-8-bit image (1 or 3 channels accepted; colour is converted to gray). */
CameraEdgeField buildCameraEdgeField(const DirectAlignmentOptions& options, const cv::Mat& image);

struct DirectAlignmentStats
{
    int iterations = 0;
    int edge_points = 0;
    double initial_edge_cost = 0, final_edge_cost = 0;  ///< mean Huber cost at the full-resolution level
    double final_inlier_ratio = 0;                      ///< share of edge points with DT < huber_px at full resolution
    double ms = 0;
    /** Gauss-Newton Hessian of the mean edge cost at the final pose, full resolution, prior excluded (tangent
     *  [dtheta; dp] of T_world_cam, camera frame): how well the map edges pin each direction down. */
    Eigen::Matrix<double, 6, 6> hessian = Eigen::Matrix<double, 6, 6>::Zero();
};

/** Mean Huber cost of the edge residuals at pyramid level `level` (points outside the image or beyond the
 *  truncation count as truncation_px), and the share within huber_px. */
double edgeCost(const DirectAlignmentOptions& options, const CameraEdgeField& field, int level,
                const core::CameraModel& camera, const DirectAlignmentModel& model,
                const Eigen::Isometry3d& T_world_cam, double* inlier_ratio = nullptr);

/** NMI = (H(A) + H(B)) / H(A, B) in [1, 2] between the camera intensity at the projections of the NMI samples
 *  and their reflectivity; 1 when fewer than 50 points project into the image. */
double normalizedMutualInformation(const DirectAlignmentOptions& options, const CameraEdgeField& field,
                                   const core::CameraModel& camera, const NmiSamples& samples,
                                   const Eigen::Isometry3d& T_world_cam);

/** A Gaussian prior on the pose (e.g. the IMU prediction with its uncertainty), added to the mean edge cost as
 *  weight * 0.5 |(T (-) T_prior) / sigma|^2: it keeps the coarse levels from wandering to clutter far outside
 *  the prediction's uncertainty. */
struct DirectPrior
{
    Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
    double sigma_m = 1, sigma_rad = 0.1;
    double weight = 1;
};

/** Refines T_world_cam (in: initial guess, out: estimate). Returns false (pose unchanged) when the model
 *  has fewer than 20 edge points or the normal equations are singular at every level. */
bool alignDirect(const DirectAlignmentOptions& options, const CameraEdgeField& field, const core::CameraModel& camera,
                 const DirectAlignmentModel& model, Eigen::Isometry3d& T_world_cam,
                 DirectAlignmentStats* stats = nullptr, const DirectPrior* prior = nullptr);

}  // namespace quasiloc::estimation
