#include <algorithm>
#include <chrono>
#include <ctime>
#include <quasiloc/core/error.h>
#include <quasiloc/map/map_build.h>

namespace quasiloc::map
{
namespace
{
struct PassClock
{
    std::chrono::steady_clock::time_point wall = std::chrono::steady_clock::now();
    std::clock_t cpu = std::clock();
    void stop(MapBuildResult& r, int pass) const
    {
        r.seconds[pass] = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count();
        r.cpu_seconds[pass] = double(std::clock() - cpu) / CLOCKS_PER_SEC;
    }
};

/** Every pass reads each scan the same way: f(world scan, index, points read, points without a position). */
template <class F>
void forEachScan(const ScanSource& source, const ScanPoses& poses, const ScanFilter& filter, int pass,
                 const MapBuildProgress& progress, F&& f)
{
    source.forEach([&](size_t i, LidarScan&& scan) {
        const size_t read = scan.size(), invalid = scan.invalid_points;
        f(toWorld(std::move(scan), poses, i, filter), i, read, invalid);
        if (progress) progress(pass, i + 1, source.size());
    });
}
}  // namespace

MapBuildResult buildMap(const MapBuildOptions& o, const ScanSource& source, const ScanPoses& poses,
                        const MapBuildProgress& progress)
{
    core::require(poses.size() == source.size(), "map-build", "one pose per scan expected");
    const ScanFilter filter = o.scanFilter();
    MapBuildResult r;
    r.scans = source.size();
    VoxelFusion fusion(o.voxel_size_m);
    FreeSpaceCarver carver(o.carvingOptions());
    float raw_min = std::numeric_limits<float>::infinity(), raw_max = -raw_min;

    PassClock clock;
    forEachScan(source, poses, filter, 1, progress, [&](const WorldScan& w, size_t i, size_t read, size_t invalid) {
        r.points_read += read;
        r.points_invalid += invalid;
        r.points_used += w.size();
        r.deskewed_scans += w.deskewed;
        fusion.addGeometry(w, source.name(i));
        if (o.carve) carver.addHits(w, int(i));
        for (float v : w.intensity) raw_min = std::min(raw_min, v), raw_max = std::max(raw_max, v);
    });
    core::require(r.points_used > 0, o.scansName(), "no point within the range limits in any scan");
    clock.stop(r, 0);

    const bool per_ring = o.reflectivity_normalisation == ReflectivityNormalisation::Ring ||
                          o.reflectivity_normalisation == ReflectivityNormalisation::RangeRing;
    const bool per_range = o.reflectivity_normalisation == ReflectivityNormalisation::Range ||
                           o.reflectivity_normalisation == ReflectivityNormalisation::RangeRing;
    ReflectivityModel model(per_ring, per_range, o.range_bin_m, o.max_range_m);
    clock = PassClock();
    if (o.carve) carver.finishHits();
    if (o.carve || per_ring || per_range)
        forEachScan(source, poses, filter, 2, progress, [&](const WorldScan& w, size_t i, size_t, size_t) {
            if (o.carve) carver.castRays(w, int(i));
            model.observe(w, fusion);
        });
    model.fit();
    clock.stop(r, 1);

    // Reflectivities: the model's corrections (pass 3), or the raw means. Then raw -> [0, 1] by the import rule.
    clock = PassClock();
    const bool normalised = per_ring || per_range;
    if (normalised)
        forEachScan(source, poses, filter, 3, progress,
                    [&](const WorldScan& w, size_t, size_t, size_t) { fusion.addReflectivity(w, model); });
    clock.stop(r, 2);
    r.intensity = chooseIntensityNormalisation({raw_min, raw_max}, o.intensity_scale, "[MapBuild] intensity_scale");
    const float inv_divisor = float(1.0 / r.intensity.divisor);
    r.map.reserve(fusion.size());
    fusion.forEachPoint([&](const Eigen::Vector3f& p, const FusedVoxel& v) {
        float refl = (normalised ? v.refl_sum : v.raw_sum) / float(v.count) * inv_divisor;
        if (refl < 0 || refl > 1) ++r.reflectivity_clamped, refl = std::clamp(refl, 0.f, 1.f);
        (o.carve && carver.isFree(p) ? r.removed : r.map).addPoint(p.x(), p.y(), p.z(), refl);
    });
    core::require(!r.map.empty(), o.output, "the carving removed every point (check carve_* options and poses)");
    r.fused_voxels = fusion.size();
    r.fusion_bytes = fusion.memoryBytes();
    if (o.carve) r.carving = carver.stats();
    r.consistency = normalised ? fusion.consistency() : ReflectivityConsistency{};
    r.reflectivity_model = model.summary();
    return r;
}

}  // namespace quasiloc::map
