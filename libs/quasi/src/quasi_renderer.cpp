#include <atomic>
#include <chrono>
#include <ctime>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <quasiloc/core/error.h>
#include <quasiloc/quasi/quasi_renderer.h>

#include "render_stages.h"

namespace quasiloc::quasi
{

struct QuasiRenderer::Buffers
{
    std::optional<detail::FastProjector> cam;
    map::VisibilityIndex::ViewCone cone;
    std::vector<map::VisibilityIndex::Range> ranges;
    std::vector<detail::ZBuffer> zbs;          ///< one, shared by the projection threads (each owns a block of rows)
    std::vector<int32_t> proj_pix;             ///< per candidate: pixel (-1: rejected), with several threads
    std::vector<float> proj_depth;             ///< per candidate: camera z
    detail::SparsePlanes sparse;               ///< the z-buffer image
    detail::SparsePlanes unsplatted;           ///< its copy before splatting
    cv::Mat window_min;                        ///< its minimum over the see-through window
    std::vector<std::vector<int32_t>> hidden;  ///< per row stripe: pixels the see-through filter drops
    std::vector<std::vector<uint32_t>> histograms;  ///< per row stripe
    std::vector<size_t> counts;                     ///< per row stripe
    detail::HueTable hue;
    int num_threads = 1;
};

namespace
{
/** Wall and process-CPU clocks for the per-stage split. */
struct StageClock
{
    std::chrono::steady_clock::time_point wall = std::chrono::steady_clock::now();
    double cpu = cpuMs();
    static double cpuMs()
    {
        timespec ts;
        clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
        return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
    }
    /** Milliseconds (wall, cpu) since the previous lap. */
    void lap(double& wall_ms, double& cpu_ms)
    {
        const auto now = std::chrono::steady_clock::now();
        const double c = cpuMs();
        wall_ms = std::chrono::duration<double, std::milli>(now - wall).count();
        cpu_ms = c - cpu;
        wall = now;
        cpu = c;
    }
};

/** Runs f(y0, y1, stripe) over `stripes` row stripes of an image of `height` rows in parallel. */
template <class F>
void parallelRows(int height, int stripes, F&& f)
{
    cv::parallel_for_(
        cv::Range(0, stripes),
        [&](const cv::Range& r) {
            for (int s = r.start; s < r.end; ++s) f(height * s / stripes, height * (s + 1) / stripes, s);
        },
        stripes);
}

size_t sum(const std::vector<size_t>& v)
{
    size_t n = 0;
    for (size_t x : v) n += x;
    return n;
}
}  // namespace

QuasiRenderer::QuasiRenderer(const map::LidarMap& map, std::shared_ptr<const map::VisibilityIndex> index,
                             const QuasiOptions& options)
    : map_(map), index_(std::move(index)), options_(options), buf_(std::make_unique<Buffers>())
{
    core::require(index_ != nullptr, "QuasiRenderer visibility index", "is missing");
    options_.check("QuasiRenderer options");
    core::require(!map.empty(), "QuasiRenderer map", "the map is empty");
    core::require(map.size() < (size_t(1) << 31), "QuasiRenderer map", "more than 2^31 points");
    core::require(index_->size() == map.size(), "QuasiRenderer visibility index",
                  "holds " + std::to_string(index_->size()) + " points but the map " + std::to_string(map.size()));
    buf_->num_threads = options_.num_threads > 0 ? options_.num_threads : std::max(1, cv::getNumThreads());
    buf_->hue = detail::HueTable::make(options_);
    buf_->histograms.assign(4 * buf_->num_threads, std::vector<uint32_t>(detail::kReflHistogramBins, 0));
    buf_->counts.assign(4 * buf_->num_threads, 0);
    buf_->hidden.resize(4 * buf_->num_threads);

    std::vector<uint32_t> hist(detail::kReflHistogramBins, 0);
    const float* r = index_->reflectivities();
    for (size_t i = 0; i < index_->size(); ++i)
        ++hist[std::min(detail::kReflHistogramBins - 1, std::max(0, int(r[i] * detail::kReflHistogramBins)))];
    detail::reflectivityPercentiles(hist, options_, map_refl_lo_, map_refl_hi_);
}

QuasiRenderer::QuasiRenderer(const map::LidarMap& map, const QuasiOptions& options)
    : QuasiRenderer(map,
                    std::make_shared<const map::VisibilityIndex>(
                        map, map::VisibilityIndex::Options{options.visibility_block_size_m}),
                    options)
{}

QuasiRenderer::~QuasiRenderer() = default;

void QuasiRenderer::render(const mrpt::poses::CPose3D& T_world_cam, const core::CameraModel& camera, QuasiImage& out,
                           bool encode, int completion_radius_px)
{
    core::require(completion_radius_px <= options_.completion_radius_px, "QuasiRenderer::render completion_radius_px",
                  std::to_string(completion_radius_px) + " exceeds the options' " +
                      std::to_string(options_.completion_radius_px) + " (the buffers' margin)");
    Buffers& b = *buf_;
    QuasiOptions o = options_;
    if (completion_radius_px >= 0) o.completion_radius_px = completion_radius_px;
    StageClock clock;
    const detail::PoseF pose = detail::PoseF::camFromWorld(T_world_cam);

    // Image-sized buffers follow the camera; they are (re)allocated only when it changes.
    if (!b.cam || !b.cam->sameCamera(camera))
    {
        b.cam = detail::FastProjector::fromCamera(camera);
        b.cone = map::VisibilityIndex::viewCone(camera);
        const size_t n = size_t(camera.width) * camera.height;
        b.zbs.resize(1);
        for (auto& zb : b.zbs)
        {
            zb.key.assign(n, detail::kEmptyKey);
            zb.refl.assign(n, 0.f);
        }
        // Empty margin for the window loops of the see-through filter and completion (no border tests).
        b.sparse.create(camera.width, camera.height,
                        std::max(options_.completion_radius_px, options_.occlusion_radius_px));
    }
    const int W = camera.width, H = camera.height;
    out.T_world_cam = T_world_cam;
    out.camera = camera;
    out.stats = RenderStats{};
    RenderStats& st = out.stats;

    index_->query(T_world_cam, b.cone, o.max_depth_m, b.ranges);
    st.candidate_points = map::VisibilityIndex::countPoints(b.ranges);
    clock.lap(st.ms_culling, st.cpu_ms_culling);

    // Projection into one z-buffer. With several threads: first each projects its share of the candidates into
    // the pixel/depth buffers, then each runs the z-buffer test of all of them for its own block of rows. No
    // per-thread z-buffers to merge, and the result is the one-thread result (keys are unique).
    const int S = b.num_threads;
    const int32_t n_pix = W * H;
    const size_t n_cand = st.candidate_points;
    const float min_depth = float(o.min_depth_m), max_depth = float(o.max_depth_m);
    if (S == 1)
    {
        b.counts[0] =
            detail::projectPoints(*index_, b.ranges, 0, n_cand, *b.cam, pose, min_depth, max_depth, 0, n_pix, b.zbs[0]);
        detail::mergeZBuffers(b.zbs, 0, H, b.sparse);
    }
    else
    {
        // Candidate-sized, kept between renders: reallocated only when a view has more candidates than any
        // before, with headroom so that this stays rare.
        if (b.proj_pix.size() < n_cand)
        {
            const size_t n = std::min(index_->size(), n_cand + n_cand / 4);
            b.proj_pix.resize(n), b.proj_depth.resize(n);
        }
        cv::parallel_for_(
            cv::Range(0, S),
            [&](const cv::Range& r) {
                for (int s = r.start; s < r.end; ++s)
                    detail::projectToBuffer(*index_, b.ranges, n_cand * s / S, n_cand * (s + 1) / S, *b.cam, pose,
                                            min_depth, max_depth, b.proj_pix.data(), b.proj_depth.data());
            },
            S);
        // Each thread's block of rows: z-buffer test, then the sparse planes of those rows (still in cache).
        parallelRows(H, S, [&](int y0, int y1, int s) {
            b.counts[s] = detail::zTestBuffer(*index_, b.ranges, b.proj_pix.data(), b.proj_depth.data(), y0 * W, y1 * W,
                                              b.zbs[0]);
            detail::mergeZBuffers(b.zbs, y0, y1, b.sparse);
        });
    }
    for (int s = 0; s < S; ++s) st.projected_points += b.counts[s];
    const int row_stripes = int(b.counts.size());
    if (o.point_size_m > 0 && o.max_splat_radius_px > 0)
    {
        if (b.unsplatted.depth.size() != cv::Size(W, H)) b.unsplatted.create(W, H);
        b.sparse.depth.copyTo(b.unsplatted.depth);
        b.sparse.refl.copyTo(b.unsplatted.refl);
        b.sparse.index.copyTo(b.unsplatted.index);
        const float radius_px_at_1m = float(0.5 * camera.fx * o.point_size_m);
        parallelRows(H, row_stripes, [&](int y0, int y1, int s) {
            b.counts[s] = detail::splatRows(b.unsplatted, y0, y1, radius_px_at_1m, o.max_splat_radius_px, b.sparse);
        });
        st.splatted_pixels = sum(b.counts);
    }
    clock.lap(st.ms_projection, st.cpu_ms_projection);

    // See-through filter, then completion into the output images.
    out.depth.create(H, W, CV_32FC1);
    out.reflectivity.create(H, W, CV_32FC1);
    out.valid.create(H, W, CV_8UC1);
    out.sparse.create(H, W, CV_8UC1);
    out.provenance.create(H, W, CV_32SC1);
    if (o.occlusion_radius_px > 0)
    {
        const int D = 2 * o.occlusion_radius_px + 1;
        cv::erode(b.sparse.depth, b.window_min, cv::Mat::ones(D, D, CV_8U), cv::Point(-1, -1), 1, cv::BORDER_CONSTANT,
                  cv::Scalar(detail::kNoDepth));
        parallelRows(H, row_stripes, [&](int y0, int y1, int s) {
            b.hidden[s].clear();
            detail::findSeeThrough(b.sparse, b.window_min, y0, y1, o, b.hidden[s]);
        });
        // Applied after every stripe has decided: the decisions read the unfiltered image.
        for (const auto& hidden : b.hidden)
        {
            for (const int32_t p : hidden)
            {
                b.sparse.depth.ptr<float>(p / W)[p % W] = detail::kNoDepth;  // planes with a margin: by row
                b.sparse.index.ptr<int32_t>(p / W)[p % W] = -1;
            }
            st.occluded_pixels += hidden.size();
        }
    }
    parallelRows(H, row_stripes,
                 [&](int y0, int y1, int s) { b.counts[s] = detail::completeRows(b.sparse, y0, y1, o, out); });
    st.completed_pixels = sum(b.counts);
    if (o.scanline_gap_px > 0)
    {
        // By column stripes: each column is filled independently.
        parallelRows(W, row_stripes, [&](int x0, int x1, int s) {
            b.counts[s] = detail::fillScanlineGapColumns(out, x0, x1, o.scanline_gap_px, o.completion_depth_rel);
        });
        st.scanline_filled_pixels = sum(b.counts);
    }
    clock.lap(st.ms_completion, st.cpu_ms_completion);
    if (!encode)
    {
        out.bgr.release();
        out.gray.release();
        st.sparse_pixels = size_t(cv::countNonZero(out.sparse));
        return;
    }

    // Encoding (histogram of the completed reflectivity for reflectivity_scope = image).
    out.bgr.create(H, W, CV_8UC3);
    out.gray.create(H, W, CV_8UC1);
    float lo = map_refl_lo_, hi = map_refl_hi_;
    if (o.reflectivityScope() == ReflectivityScope::Image)
    {
        parallelRows(H, row_stripes, [&](int y0, int y1, int s) {
            b.counts[s] = detail::reflectivityHistogramRows(out, y0, y1, b.histograms[s]);
        });
        for (size_t s = 1; s < b.histograms.size(); ++s)
            for (int i = 0; i < detail::kReflHistogramBins; ++i) b.histograms[0][i] += b.histograms[s][i];
        detail::reflectivityPercentiles(b.histograms[0], o, lo, hi);
        st.sparse_pixels = sum(b.counts);
    }
    else
        st.sparse_pixels = size_t(cv::countNonZero(out.sparse));
    parallelRows(H, row_stripes, [&](int y0, int y1, int) { detail::encodeRows(out, y0, y1, lo, hi, b.hue, o); });
    clock.lap(st.ms_encoding, st.cpu_ms_encoding);
}

}  // namespace quasiloc::quasi
