#pragma once
// Internal stages of QuasiRenderer, separated so that each stays small and testable.
#include <cstdint>
#include <limits>
#include <mrpt/poses/CPose3D.h>
#include <opencv2/core.hpp>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/map/visibility_index.h>
#include <quasiloc/quasi/quasi_image.h>
#include <quasiloc/quasi/quasi_options.h>
#include <vector>

namespace quasiloc::quasi::detail
{
/** Empty z-buffer slot: larger than every key (a finite positive float's bits are < 0x7f800000). */
constexpr uint64_t kEmptyKey = std::numeric_limits<uint64_t>::max();

/** The sparse (z-buffer) image as planes: the winning point's depth (+inf: no point), reflectivity and map
 *  index (-1: no point). Planes rather than a struct per pixel so that window loops stay branch-free. */
struct SparsePlanes
{
    cv::Mat depth;  ///< CV_32FC1
    cv::Mat refl;   ///< CV_32FC1
    cv::Mat index;  ///< CV_32SC1
    /** Rows and columns of empty pixels (+inf, 0, -1) readable around each plane (the planes are views into
     *  larger Mats), so that window loops need no border tests. 0 for plain Mats. */
    int margin = 0;
    /** Allocates the planes with `margin` empty pixels around them (written once here; the stages only
     *  write inside). */
    void create(int width, int height, int margin = 0);
};
constexpr float kNoDepth = std::numeric_limits<float>::infinity();

/** The camera model prepared for float projection of many points. Points whose undistorted normalised
 *  coordinates fall outside the box of the image (plus a margin) or beyond the radius where the radial
 *  distortion folds back are rejected before distortion, so no point from far outside the field of view can
 *  wrap into the image through the polynomial. */
struct FastProjector
{
    int width = 0, height = 0;
    float fx = 0, fy = 0, cx = 0, cy = 0;
    core::DistortionModel model = core::DistortionModel::None;
    float k[5] = {0, 0, 0, 0, 0};
    float xn_min = 0, xn_max = 0, yn_min = 0, yn_max = 0;
    float r2_max = std::numeric_limits<float>::infinity();
    core::CameraModel source;  ///< the model this was built from (to detect a change)

    static FastProjector fromCamera(const core::CameraModel& camera);
    bool sameCamera(const core::CameraModel& camera) const;
};

/** T_cam_world as float, for the projection loop. */
struct PoseF
{
    float R[9];
    float t[3];
    static PoseF camFromWorld(const mrpt::poses::CPose3D& T_world_cam);
};

/** Z-buffer: keys (depth bits << 32 | map index) and the winner's reflectivity. */
struct ZBuffer
{
    std::vector<uint64_t> key;
    std::vector<float> refl;
    size_t projected = 0;
};

/** Projects the points of `ranges` in [first, last) of their concatenation into `zb`. */
void projectPoints(const map::VisibilityIndex& index, const std::vector<map::VisibilityIndex::Range>& ranges,
                   size_t first, size_t last, const FastProjector& cam, const PoseF& pose, float min_depth,
                   float max_depth, ZBuffer& zb);
/** The same for the pixels [pix_begin, pix_end) (y * width + x) only. Returns the points projected into the
 *  range. */
size_t projectPoints(const map::VisibilityIndex& index, const std::vector<map::VisibilityIndex::Range>& ranges,
                     size_t first, size_t last, const FastProjector& cam, const PoseF& pose, float min_depth,
                     float max_depth, int32_t pix_begin, int32_t pix_end, ZBuffer& zb);

/** Projection in two steps, for threads sharing one z-buffer without each projecting every point: first the
 *  pixel (-1: rejected) and depth of the points in [first, last) of the concatenated ranges, at those
 *  positions of `pix` and `depth` (sized for all candidates); then the z-buffer test of all of them for the
 *  pixels [pix_begin, pix_end) only (returns how many). Same result as projectPoints. */
void projectToBuffer(const map::VisibilityIndex& index, const std::vector<map::VisibilityIndex::Range>& ranges,
                     size_t first, size_t last, const FastProjector& cam, const PoseF& pose, float min_depth,
                     float max_depth, int32_t* pix, float* depth);
size_t zTestBuffer(const map::VisibilityIndex& index, const std::vector<map::VisibilityIndex::Range>& ranges,
                   const int32_t* pix, const float* depth, int32_t pix_begin, int32_t pix_end, ZBuffer& zb);

/** Rows [y0, y1): sparse = the minimum key over all z-buffers (the renderer uses one); resets the z-buffers
 *  to empty. */
void mergeZBuffers(std::vector<ZBuffer>& zbs, int y0, int y1, SparsePlanes& sparse);

/** Rows [y0, y1) of `dst` (a copy of `src` on entry): every point of `src` at depth z also covers the square of
 *  half-width r = min(max_radius_px, floor(radius_px_at_1m / z)) around its pixel, where it wins a pixel whose
 *  depth is larger (ties: the smaller map index). Reads the source rows within max_radius_px of [y0, y1), so
 *  stripes can run in parallel. Returns the number of pixels that were empty and are now covered. */
size_t splatRows(const SparsePlanes& src, int y0, int y1, float radius_px_at_1m, int max_radius_px, SparsePlanes& dst);

/** Rows [y0, y1) of the see-through filter: appends to `hidden` the pixels (y * width + x) it drops.
 *  window_min = minimum of sparse.depth over the (2R+1)^2 window (a cheap pre-test). */
void findSeeThrough(const SparsePlanes& sparse, const cv::Mat& window_min, int y0, int y1, const QuasiOptions& o,
                    std::vector<int32_t>& hidden);

/** Rows [y0, y1) of cross-guided completion from `sparse` into out.depth/reflectivity/valid/sparse/provenance.
 *  Returns the number of completed pixels. allow_simd = false forces the scalar reference path (tests).
 *  Completed pixel: reference = the nearest sparse pixel in the image (ties: nearer depth); i = max
 *  reflectivity over the window pixels within completion_depth_rel of the reference's depth; depth = mean over
 *  those also within completion_reflectivity_abs of i; provenance = the nearest of the latter in the image
 *  (ties: nearer depth, then smaller map index). */
size_t completeRows(const SparsePlanes& sparse, int y0, int y1, const QuasiOptions& o, QuasiImage& out,
                    bool allow_simd = true);

/** Columns [x0, x1) of scan-line gap filling (QuasiOptions::scanline_gap_px) in the completed out.depth,
 *  reflectivity, valid and provenance: a vertical run of 1..max_gap_px invalid pixels between two valid ones whose
 *  depths agree within depth_rel (of the nearer) gets inverse depth and reflectivity interpolated linearly along
 *  the column (a plane's inverse depth is linear in the image) and the provenance of the nearer end; `sparse` is
 *  left 0. Returns the number of filled pixels. */
size_t fillScanlineGapColumns(QuasiImage& out, int x0, int x1, int max_gap_px, double depth_rel);
/** Look-up table of the HSV colour at V = 1 for 256 levels of h(I) (BGR, 0..1) and its luminance. */
struct HueTable
{
    float bgr[256][3];
    float luminance[256];
    alignas(16) float bgrl[256][4];  ///< (b, g, r, luminance) per level, for a 4-lane encoder
    static HueTable make(const QuasiOptions& o);
};

/** Low and high reflectivity percentiles of the valid pixels of `q` (or of a sample of values). */
void reflectivityPercentiles(const std::vector<uint32_t>& histogram, const QuasiOptions& o, float& lo, float& hi);
constexpr int kReflHistogramBins = 1024;
/** Rows [y0, y1): `histogram` (kReflHistogramBins bins over [0, 1], overwritten) of the reflectivity of the
 *  valid pixels of `q`. Returns the number of sparse pixels in those rows. */
size_t reflectivityHistogramRows(const QuasiImage& q, int y0, int y1, std::vector<uint32_t>& histogram);

/** Rows [y0, y1) of the encoding of q.depth/q.reflectivity/q.valid into q.bgr and q.gray. */
void encodeRows(QuasiImage& q, int y0, int y1, float refl_lo, float refl_hi, const HueTable& hue,
                const QuasiOptions& o);

}  // namespace quasiloc::quasi::detail
