#include <quasiloc/core/error.h>
#include <quasiloc/frontend/lifting.h>
#include <quasiloc/map/visibility_index.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <quasiloc/reloc/database_builder.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <opencv2/core/utility.hpp>
#include <thread>
#include <tuple>

namespace quasiloc::reloc
{
namespace
{
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

const Eigen::Vector3f kNaN3 = Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());

/** One worker's renderer, extractor and detector (none of them is thread-safe). */
struct Worker
{
    Worker(const map::LidarMap& map, std::shared_ptr<const map::VisibilityIndex> index, const DatabaseBuildConfig& cfg)
        : renderer(map, index, cfg.quasi), extractor(frontend::createFeatureExtractor(cfg.features)), lines(cfg.lines)
    {}
    quasi::QuasiRenderer renderer;
    std::unique_ptr<frontend::FeatureExtractor> extractor;
    frontend::LineDetector lines;
    quasi::QuasiImage q;
    frontend::Features features;
    cv::Mat blurred;
};

/** Renders, extracts and lifts one view; false when it sees too little of the map (counted in `dropped_*`). */
bool processView(Worker& w, const map::LidarMap& map, const core::CameraModel& camera, const DatabaseBuildConfig& cfg,
                 const mrpt::poses::CPose3D& T_world_cam, DatabaseView& view, bool& dropped_for_valid)
{
    w.renderer.render(T_world_cam, camera, w.q);
    view.T_world_cam = T_world_cam;
    view.valid_fraction = float(cv::countNonZero(w.q.valid)) / float(w.q.valid.total());
    dropped_for_valid = view.valid_fraction < cfg.build.min_valid_fraction;
    if (dropped_for_valid) return false;
    preprocessImage(w.q.gray, cfg.build.image_blur_sigma_px, w.blurred);
    w.extractor->extract(w.blurred, w.q.valid, w.features);
    view.points.keypoints = w.features.keypoints;
    view.points.descriptors = w.features.descriptors.clone();
    view.points.type = w.features.type;
    view.points.image_size = w.features.image_size;
    view.points_world.assign(view.points.size(), kNaN3);
    int lifted = 0;
    for (size_t i = 0; i < view.points.size(); ++i)
        if (auto p = frontend::liftPixel(w.q, map, view.points.keypoints[i].pt, cfg.association.lift_search_radius_px))
        {
            view.points_world[i] = p->p_world;
            ++lifted;
        }
    if (lifted < cfg.build.min_lifted) return false;
    if (cfg.build.store_lines)
    {
        for (const auto& seg : w.lines.detect(w.q.gray, w.q.valid))
        {
            const frontend::LineSupport s = frontend::lineSupport(w.q, map, seg, cfg.association);
            std::array<Eigen::Vector3f, 2> ends{kNaN3, kNaN3};
            if (s.valid())
            {
                // The support's extent along its fitted line gives the 3D segment.
                float lo = std::numeric_limits<float>::max(), hi = -lo;
                for (const auto& p : s.points)
                {
                    const float t = (p - s.line_point).dot(s.line_direction);
                    lo = std::min(lo, t);
                    hi = std::max(hi, t);
                }
                ends = {s.line_point + lo * s.line_direction, s.line_point + hi * s.line_direction};
            }
            view.lines.push_back(seg);
            view.lines_world.push_back(ends);
        }
    }
    return true;
}

struct RenderedViews
{
    std::vector<DatabaseView> views;  ///< one per selected view
    std::vector<char> keep, dropped_valid;
    double ms_per_view_cpu = 0;
};

/** processView() on every selected sample on `threads` workers; the result does not depend on their number. */
RenderedViews renderViews(const map::LidarMap& map, const core::CameraModel& camera, const DatabaseBuildConfig& cfg,
                          const std::vector<mrpt::poses::CPose3D>& poses, const std::vector<size_t>& selected,
                          int threads, const BuildProgress& progress)
{
    RenderedViews r;
    const size_t n = selected.size();
    r.views.resize(n);
    r.keep.assign(n, 0);
    r.dropped_valid.assign(n, 0);
    if (n == 0) return r;
    const auto index = std::make_shared<const map::VisibilityIndex>(
        map, map::VisibilityIndex::Options{cfg.quasi.visibility_block_size_m});
    std::atomic<size_t> next{0}, done{0};
    std::atomic<double> cpu_ms{0};
    std::mutex progress_mutex;
    std::exception_ptr failure;
    const size_t report_every = std::max<size_t>(1, n / 100);
    const int saved_cv_threads = cv::getNumThreads();
    cv::setNumThreads(1);  // OpenCV's own pool would fight the workers for the same cores
    auto work = [&]() {
        try
        {
            Worker w(map, index, cfg);
            for (size_t i = next++; i < n; i = next++)
            {
                const auto tv = Clock::now();
                bool low_valid = false;
                r.keep[i] = processView(w, map, camera, cfg, poses[selected[i]], r.views[i], low_valid) ? 1 : 0;
                r.dropped_valid[i] = low_valid ? 1 : 0;
                double expected = cpu_ms.load();
                while (!cpu_ms.compare_exchange_weak(expected, expected + msSince(tv)))
                {}
                const size_t d = ++done;
                if (progress && (d % report_every == 0 || d == n))
                {
                    std::lock_guard<std::mutex> lock(progress_mutex);
                    progress(d, n);
                }
            }
        }
        catch (...)
        {
            std::lock_guard<std::mutex> lock(progress_mutex);
            if (!failure) failure = std::current_exception();
            next = n;
        }
    };
    std::vector<std::thread> pool;
    for (int k = 1; k < threads; ++k) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
    cv::setNumThreads(saved_cv_threads);
    if (failure) std::rethrow_exception(failure);
    r.ms_per_view_cpu = cpu_ms.load() / double(n);
    return r;
}

/** The build's options as the workers use them. */
DatabaseBuildConfig workerConfig(const DatabaseBuildConfig& config)
{
    DatabaseBuildConfig cfg = config;
    // Workers render single-threaded: views are the parallel unit.
    cfg.quasi.num_threads = 1;
    // Views are extracted with the quasi-image's validity mask, queries without one: both must use the same
    // detector threshold or the two sides find different corners (15 vs 9 of 20 between-view queries localized
    // in reloc_unittests when the masked threshold was 20 and the query's 12).
    cfg.features.orb_fast_threshold_masked = cfg.features.orb_fast_threshold;
    return cfg;
}

/** Moves the kept views into the shard (id = sample index) and counts the dropped ones. */
void keepViews(RenderedViews& r, const std::vector<size_t>& selected, DatabaseShard& s, DatabaseBuildStats& st)
{
    for (size_t i = 0; i < selected.size(); ++i)
    {
        if (!r.keep[i])
        {
            (r.dropped_valid[i] ? st.dropped_valid : st.dropped_lifted)++;
            continue;
        }
        r.views[i].id = int(selected[i]);
        s.views.push_back(std::move(r.views[i]));
    }
    s.dropped_valid = st.dropped_valid;
    s.dropped_lifted = st.dropped_lifted;
    st.kept = s.views.size();
}

/** The shards' views in the order of the sampled views, whichever shard rendered them, with ids 0..: the ids and
 *  the order of a single-process build. */
Database joinShards(std::vector<DatabaseShard>& shards, DatabaseBuildStats& st)
{
    const int n = int(shards.size());
    const DatabaseShard& first = shards.front();
    std::vector<std::tuple<int, int, size_t>> order;  // (sample index, shard, position in the shard)
    for (int k = 0; k < n; ++k)
    {
        const DatabaseShard& s = shards[size_t(k)];
        core::require(s.selection == ShardSelection{k, n} && s.sampled_views == first.sampled_views,
                      "shard " + std::to_string(k) + " of " + std::to_string(n),
                      "holds shard " + s.selection.text() + " of " + std::to_string(s.sampled_views) +
                          " sampled views: shards must be given in order, all N of them, of one build");
        st.rendered += s.rendered;
        st.dropped_valid += s.dropped_valid;
        st.dropped_lifted += s.dropped_lifted;
        for (size_t j = 0; j < s.views.size(); ++j) order.emplace_back(s.views[j].id, k, j);
    }
    st.sampled = first.sampled_views;
    std::sort(order.begin(), order.end());
    for (size_t i = 1; i < order.size(); ++i)
        core::require(std::get<0>(order[i]) != std::get<0>(order[i - 1]),
                      "shards " + std::to_string(std::get<1>(order[i - 1])) + " and " +
                          std::to_string(std::get<1>(order[i])) + " of " + std::to_string(n),
                      "both hold view " + std::to_string(std::get<0>(order[i])));

    Database db;
    db.camera = first.camera;
    db.features = first.features;
    db.image_blur_sigma_px = first.image_blur_sigma_px;
    db.map_points = first.map_points;
    db.views.reserve(order.size());
    for (const auto& [sample, k, j] : order)
    {
        db.views.push_back(std::move(shards[size_t(k)].views[j]));
        db.views.back().id = int(db.views.size()) - 1;
    }
    st.kept = db.views.size();
    return db;
}
}  // namespace

void DatabaseBuildOptions::declare(core::OptionTable& t)
{
    using core::Range;
    t.add("min_valid_fraction", min_valid_fraction, "", Range::between(0, 1),
          "a view whose quasi-image has fewer valid pixels is dropped (looks at a void)");
    t.add("min_lifted", min_lifted, "", Range::atLeast(0),
          "a view with fewer keypoints lifted to the map is dropped (nothing to localize with)");
    t.add("store_lines", store_lines, "detect and lift line segments too ([Lines] options)");
    t.add("threads", threads, "", Range::atLeast(0), "workers; 0 = all cores");
    t.add("image_blur_sigma_px", image_blur_sigma_px, "px", Range::between(0, 10),
          "Gaussian blur of the quasi-image (and of every query) before feature extraction (0: none)");
}

DatabaseShard buildDatabaseShard(const map::LidarMap& map, const core::CameraModel& camera,
                                 const DatabaseBuildConfig& config, ShardSelection shard, DatabaseBuildStats* stats,
                                 const BuildProgress& progress)
{
    core::require(!map.empty(), "the LiDAR map", "is empty: nothing to build a database from");
    camera.check("the database camera");
    config.build.checkRanges("BuildDatabase", "BuildDatabase");
    core::require(shard.count >= 1 && shard.index >= 0 && shard.index < shard.count, "shard " + shard.text(),
                  "the index i of i/N must be in [0, N)");
    DatabaseBuildStats st;

    auto t0 = Clock::now();
    const std::vector<mrpt::poses::CPose3D> poses = sampleViewpoints(map, config.sampling, &st.sampling);
    st.ms_sampling = msSince(t0);
    core::require(!poses.empty(), "[ViewSampling]",
                  "no viewpoint in the map's free space (check heights_m, clearance_m, region, require_enclosed)");
    core::require(size_t(shard.count) <= poses.size(), "shard " + shard.text(),
                  std::to_string(shard.count) + " shards for " + std::to_string(poses.size()) +
                      " sampled views: use at most one shard per view");
    const std::vector<size_t> selected = shardViews(poses, config.sampling.grid_spacing_m, shard);
    st.sampled = poses.size();
    st.rendered = selected.size();
    st.threads =
        config.build.threads > 0 ? config.build.threads : std::max(1, int(std::thread::hardware_concurrency()));
    st.threads = std::max(1, std::min<int>(st.threads, int(selected.size())));

    const DatabaseBuildConfig cfg = workerConfig(config);
    t0 = Clock::now();
    RenderedViews r = renderViews(map, camera, cfg, poses, selected, st.threads, progress);
    st.ms_views = msSince(t0);
    st.ms_per_view_cpu = r.ms_per_view_cpu;

    DatabaseShard s;
    s.selection = shard;
    s.map_points = map.size();
    s.options = resultOptionsText(config, camera);
    s.sampled_views = poses.size();
    s.rendered = selected.size();
    s.camera = camera;
    s.features = cfg.features;
    s.image_blur_sigma_px = config.build.image_blur_sigma_px;
    keepViews(r, selected, s, st);
    if (stats) *stats = st;
    return s;
}

Database finishDatabase(std::vector<DatabaseShard> shards, const VocabularyOptions& vocabulary,
                        DatabaseBuildStats* stats)
{
    core::require(!shards.empty(), "the database", "has no shard to finish");
    DatabaseBuildStats st;
    Database db = joinShards(shards, st);
    core::require(!db.views.empty(), "[BuildDatabase]",
                  "every sampled view was dropped (min_valid_fraction / min_lifted too strict, or the map is too "
                  "sparse for the camera)");

    auto t0 = Clock::now();
    std::vector<cv::Mat> descriptors;
    descriptors.reserve(db.views.size());
    for (const auto& v : db.views) descriptors.push_back(v.points.descriptors);
    db.vocabulary = Vocabulary::train(descriptors, vocabulary);
    st.ms_vocabulary = msSince(t0);

    t0 = Clock::now();
    for (auto& v : db.views)
    {
        v.words = db.vocabulary.words(v.points.descriptors);
        v.bow = db.vocabulary.bowVector(v.words);
        db.index.add(v.id, v.bow);
    }
    st.ms_index = msSince(t0);
    if (stats) *stats = st;
    return db;
}

Database buildDatabase(const map::LidarMap& map, const core::CameraModel& camera, const DatabaseBuildConfig& config,
                       DatabaseBuildStats* stats, const BuildProgress& progress)
{
    DatabaseBuildStats shard_stats, finish_stats;
    std::vector<DatabaseShard> whole;
    whole.push_back(buildDatabaseShard(map, camera, config, ShardSelection{0, 1}, &shard_stats, progress));
    Database db = finishDatabase(std::move(whole), config.vocabulary, &finish_stats);
    if (stats)
    {
        *stats = shard_stats;
        stats->ms_vocabulary = finish_stats.ms_vocabulary;
        stats->ms_index = finish_stats.ms_index;
    }
    return db;
}

}  // namespace quasiloc::reloc
