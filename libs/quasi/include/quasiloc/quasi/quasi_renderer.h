#pragma once
// QuasiRenderer: renders QuasiImages of one LiDAR map. Built once per map (it keeps a reference to the map
// and owns the VisibilityIndex and every per-image buffer), then render() is called per keyframe or per
// database view; it allocates nothing map-sized per image: image-sized buffers only when the camera size
// changes, and (with several threads) candidate-sized projection buffers only when a view has more candidate
// points than any before (grow-only, with headroom).
// One renderer is not thread-safe (its buffers are shared between calls): use one per thread; render()
// itself runs on num_threads threads.
//
// Pipeline (see PAPER_NOTES.md, "Quasi-image"):
//  1. culling: VisibilityIndex::query -> contiguous ranges of block-ordered points;
//  2. projection: each point in float with the camera model inline (distortion included, so Q lives in the
//     same pixel geometry as the camera image the model describes), one z-buffer on 64-bit keys
//     (float depth bits << 32 | map index): nearest point wins, exact depth ties go to the smaller map index.
//     With several threads each projects a share of the points into a pixel/depth buffer, then each runs the
//     z-buffer test of all points for its own block of rows: the minimum over unique keys does not depend on
//     the order or the scheduling, so every thread count gives the same image;
//  3. see-through filter (far points showing through the gaps of a near surface) and cross-guided
//     completion (quasi_image.h, QuasiOptions); vectorised over pixels (AVX2, chosen at run time), with an
//     empty margin around the sparse image so that windows need no border tests;
//  4. encoding H = h(I), S = s0, V = b1 + b2 * h(F(D)) -> BGR and gray.
#include <memory>
#include <mrpt/poses/CPose3D.h>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/map/visibility_index.h>
#include <quasiloc/quasi/quasi_image.h>
#include <quasiloc/quasi/quasi_options.h>

namespace quasiloc::quasi
{
class QuasiRenderer
{
   public:
    /** Uses `index`, which must have been built from `map` (renderers of one map on several threads share it: on a
     *  large map it is as big as the points). `map` must outlive the renderer. InputError for an empty map, an
     *  index of another size, or bad options. */
    QuasiRenderer(const map::LidarMap& map, std::shared_ptr<const map::VisibilityIndex> index,
                  const QuasiOptions& options);
    /** Builds the VisibilityIndex with options.visibility_block_size_m. */
    QuasiRenderer(const map::LidarMap& map, const QuasiOptions& options);
    ~QuasiRenderer();
    QuasiRenderer(const QuasiRenderer&) = delete;
    QuasiRenderer& operator=(const QuasiRenderer&) = delete;

    /** Renders the map seen by `camera` at T_world_cam into `out` (its Mats are reused when their size
     *  matches). With `encode` false only the planes are made (depth, reflectivity, valid, sparse, provenance;
     *  bgr and gray are left empty): the tracker's edge model reads nothing else, and the encoding is a fifth of a
     *  render's CPU time. `completion_radius_px` >= 0: this render's completion radius instead of the options'
     *  (at most theirs): a render at a fraction of the camera's resolution (the tracker's edge model) has holes of
     *  the same angular size in fewer pixels. InputError for a non-finite pose, an unusable camera model or a
     *  radius above the options'. */
    void render(const mrpt::poses::CPose3D& T_world_cam, const core::CameraModel& camera, QuasiImage& out,
                bool encode = true, int completion_radius_px = -1);

    const QuasiOptions& options() const { return options_; }
    const map::LidarMap& map() const { return map_; }
    const map::VisibilityIndex& visibilityIndex() const { return *index_; }
    std::shared_ptr<const map::VisibilityIndex> sharedVisibilityIndex() const { return index_; }

   private:
    struct Buffers;
    const map::LidarMap& map_;
    std::shared_ptr<const map::VisibilityIndex> index_;
    QuasiOptions options_;
    float map_refl_lo_ = 0, map_refl_hi_ = 1;  ///< map-wide percentiles (reflectivity_scope = map)
    std::unique_ptr<Buffers> buf_;
};

}  // namespace quasiloc::quasi
