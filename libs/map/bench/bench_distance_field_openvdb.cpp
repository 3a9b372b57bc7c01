// bench_distance_field_openvdb: the map's distance field built with OpenVDB 10, measured against ours
// (map::DistanceField, docs/large_maps.md). Built only where OpenVDB is installed (libs/map/CMakeLists.txt).
//
//     bench_distance_field_openvdb <map file> [--band N] [--sweeps N] [--threads N] [--values float|u16]
//                                  [--voxel M] [--max-distance M] [--ours dense|sparse|auto] [--no-check]
//
// --band: the exact band's half-width in voxels (3; 13 covers 0.5 m at 4 cm); --threads: TBB threads for the build
// (1; our sparse build uses every core); --ours: our field's layout for the check (auto).
//
// The field is ours: the unsigned distance to the nearest map point on the same voxels (centres at multiples of the
// voxel, from the map's minimum less the margin), truncated at max_distance (4 cm voxels and 0.5 m by default, the
// tracker's), sampled trilinearly with the interpolant's gradient. With OpenVDB's tools:
//   1. tools::ParticlesToLevelSet rasterises every map point as a sphere of radius 0 into a narrow band of
//      half-width N voxels: each voxel there holds min over points of |centre - point|, the exact distance;
//   2. when N voxels fall short of the truncation, tools::FastSweeping (dilateSdf's steps: Zhao's fast sweeping of
//      the Eikonal equation |grad d| = 1, `--sweeps` iterations of 8 sweeps) extends the band to it, the exact band
//      held fixed as the boundary condition; N = ceil(max_distance / voxel) rasterises the whole band exactly;
//   3. a FloatGrid with the truncation as its background keeps the voxels below it (8^3-voxel leaves); with
//      `--values u16`, a grid of 16-bit fixed point instead, ours (steps of max_distance / 65535, the top value the
//      truncation itself), so that the memory compares with ours value for value.
// Queries: the 1 M points of bench_distance_field (map points moved by up to 0.3 m, same generator and seed), the
// value by tools::BoxSampler (getValues through a ValueAccessor, trilinearInterpolation) and the gradient of the
// same interpolant from the same eight values. A ValueAccessor caches the path to the last leaf and is not
// thread-safe: each querying thread needs its own (here one thread queries, as in bench_distance_field).
//
// Prints the row of bench_distance_field's table (the active voxels' extent, the build time, grid.memUsage(), the
// peak resident memory after loading the map and after building and querying, ns per query, the mean distance);
// stage times and the other sampler paths (GridSampler::wsSample, math::BoxStencil) go to stderr. Then, unless
// --no-check, builds our field in the same process (after the peak was read) and prints two accuracy tables, over
// the queries whose cell lies wholly within the truncation in our field: OpenVDB's values and gradients against
// ours; and each field against the exact distance to the nearest map point (a nanoflann k-d tree): at the queries
// (value, and the gradient's angle to the direction away from that point), and the stored value of the voxel
// nearest each query (all, and those within 2 voxels of a point); with both fields' query times measured back to
// back, at random and in a coherent order (sorted by 8^3-voxel block).
#include <openvdb/math/Stencils.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/FastSweeping.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/ParticlesToLevelSet.h>
#include <openvdb/tree/LeafManager.h>
#include <tbb/global_control.h>

#include <nanoflann.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <quasiloc/map/distance_field.h>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

namespace
{
using namespace quasiloc;
using Clock = std::chrono::steady_clock;
using openvdb::FloatGrid;
/** 16-bit fixed point values in OpenVDB's standard tree configuration (5, 4, 3: 8^3-voxel leaves). */
using U16Grid = openvdb::Grid<openvdb::tree::Tree4<uint16_t, 5, 4, 3>::Type>;

/** A grid's stored value as a distance: a float as it is; 16 bits as ours decodes them. */
struct Decode
{
    float truncation, step;
    float operator()(float v) const { return v; }
    float operator()(uint16_t q) const { return q == 65535 ? truncation : float(q) * step; }
    uint16_t quantize(float d) const { return uint16_t(std::lround(std::min(d, truncation) / step)); }
};

double seconds(Clock::time_point since) { return std::chrono::duration<double>(Clock::now() - since).count(); }

double peakResidentMb()
{
    std::ifstream status("/proc/self/status");
    for (std::string line; std::getline(status, line);)
        if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
    return -1;
}

/** The map's points as ParticlesToLevelSet reads particles (radius 0: rasterizeSpheres(particles, 0)). */
struct MapParticles
{
    using PosType = openvdb::Vec3R;
    const map::LidarMap& map;
    size_t size() const { return map.size(); }
    void getPos(size_t n, openvdb::Vec3R& p) const { p = openvdb::Vec3R(map.xs()[n], map.ys()[n], map.zs()[n]); }
    void getPosRad(size_t n, openvdb::Vec3R& p, openvdb::Real& radius) const { getPos(n, p), radius = 0; }
};

/** The map's points as nanoflann reads a data set. */
struct MapCloud
{
    const map::LidarMap& map;
    size_t kdtree_get_point_count() const { return map.size(); }
    float kdtree_get_pt(size_t i, size_t axis) const
    {
        return axis == 0 ? map.xs()[i] : axis == 1 ? map.ys()[i] : map.zs()[i];
    }
    template <class Box>
    bool kdtree_get_bbox(Box&) const
    {
        return false;
    }
};
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, MapCloud>, MapCloud, 3>;

struct Settings
{
    std::string map_file;
    int band = 3;      ///< exact band's half-width [voxels]
    int sweeps = 1;    ///< fast sweeping iterations (8 sweeps each)
    int threads = 1;   ///< TBB threads for the build
    bool u16 = false;  ///< store 16-bit fixed point (ours) instead of floats
    double voxel_m = 0.04, max_distance_m = 0.5;
    std::string ours = "auto";
    bool check = true;
};

struct BuildTimes
{
    double raster = 0, sweep = 0, compact = 0;
    size_t swept_voxels = 0, boundary_voxels = 0;  ///< fast sweeping's unknowns and fixed values
};

/** The truncated unsigned distance field of the map with OpenVDB (steps 1-3 of the file comment). */
FloatGrid::Ptr buildVdbField(const map::LidarMap& map, const Eigen::Vector3f& origin, float voxel, float truncation,
                             const Settings& s, BuildTimes& times)
{
    using LeafT = FloatGrid::TreeType::LeafNodeType;
    const openvdb::math::Transform::Ptr xform = openvdb::math::Transform::createLinearTransform(double(voxel));
    xform->postTranslate(openvdb::Vec3d(origin.x(), origin.y(), origin.z()));

    // 1. The exact band: spheres of radius 0 hold |centre - point| within `band` voxels, CSG-unioned (the minimum).
    auto t = Clock::now();
    FloatGrid::Ptr band = FloatGrid::create(float(s.band) * voxel);  // the half-width is background / voxel
    band->setTransform(xform);
    band->setGridClass(openvdb::GRID_LEVEL_SET);
    {
        openvdb::tools::ParticlesToLevelSet<FloatGrid> raster(*band);
        raster.setRmin(0);  // its default (1.5 voxels) would skip radius-0 particles
        raster.rasterizeSpheres(MapParticles{map}, 0.0);
        raster.finalize(/*prune=*/false);
    }
    // A point exactly on a voxel centre is "inside" its sphere: ParticlesToLevelSet turns that voxel off at
    // -background; its distance is 0.
    openvdb::tree::LeafManager<FloatGrid::TreeType>(band->tree()).foreach ([](LeafT& leaf, size_t) {
        for (auto v = leaf.beginValueOff(); v; ++v)
            if (*v < 0) v.setValue(0.f), v.setValueOn();
    });
    times.raster = seconds(t);

    // 2. Fast sweeping to the truncation: a cube of ceil(truncation / voxel) - band + 2 voxels around the exact band
    //    holds every voxel within the truncation of a point.
    t = Clock::now();
    const int reach = int(std::ceil(truncation / voxel - 1e-4f));
    FloatGrid::Ptr swept = band;
    if (s.band < reach)
    {
        // tools::dilateSdf's steps, but for sweep's finalize: it makes the field's minimum its inside background,
        // which must be negative (a ValueError for an unsigned field).
        openvdb::tools::FastSweeping<FloatGrid> fs;
        if (!fs.initDilate(*band, reach - s.band + 2, openvdb::tools::NN_FACE_EDGE_VERTEX,
                           openvdb::tools::FastSweepingDomain::SWEEP_GREATER_THAN_ISOVALUE))
            throw std::runtime_error("FastSweeping::initDilate failed");
        band.reset();
        times.swept_voxels = fs.sweepingVoxelCount(), times.boundary_voxels = fs.boundaryVoxelCount();
        fs.sweep(s.sweeps, /*finalize=*/false);
        swept = fs.sdfGrid();
    }
    times.sweep = seconds(t);

    // 3. The field: the active voxels below the truncation, in leaves of a grid whose background is the truncation.
    t = Clock::now();
    FloatGrid::Ptr field = FloatGrid::create(truncation);
    field->setTransform(xform);
    field->setName("distance");
    {
        openvdb::tree::LeafManager<const FloatGrid::TreeType> leaves(swept->tree());
        std::vector<LeafT*> kept(leaves.leafCount(), nullptr);
        leaves.foreach ([&](const LeafT& in, size_t n) {
            auto out = std::make_unique<LeafT>(in.origin(), truncation, false);
            bool any = false;
            for (auto v = in.cbeginValueOn(); v; ++v)
                if (*v < truncation) out->setValueOn(v.pos(), std::max(0.f, *v)), any = true;
            if (any) kept[n] = out.release();
        });
        for (LeafT* leaf : kept)
            if (leaf) field->tree().addLeaf(leaf);  // the tree takes ownership
    }
    if (swept->tree().activeTileCount() > 0) std::cerr << "warning: the swept grid has active tiles (not kept)\n";
    swept.reset();
    times.compact = seconds(t);
    return field;
}

/** The float field in 16-bit fixed point (step 3's `--values u16`), leaf by leaf. */
U16Grid::Ptr toU16(const FloatGrid& field, const Decode& decode)
{
    using LeafT = U16Grid::TreeType::LeafNodeType;
    U16Grid::Ptr out = U16Grid::create(uint16_t(65535));
    out->setTransform(field.transform().copy());
    openvdb::tree::LeafManager<const FloatGrid::TreeType> leaves(field.tree());
    std::vector<LeafT*> kept(leaves.leafCount(), nullptr);
    leaves.foreach ([&](const FloatGrid::TreeType::LeafNodeType& in, size_t n) {
        auto leaf = std::make_unique<LeafT>(in.origin(), uint16_t(65535), false);
        for (auto v = in.cbeginValueOn(); v; ++v) leaf->setValueOn(v.pos(), decode.quantize(*v));
        kept[n] = leaf.release();
    });
    for (LeafT* leaf : kept) out->tree().addLeaf(leaf);
    return out;
}

/** The trilinear value at p (world) and its gradient, from the eight voxels BoxSampler reads through `acc`. */
template <class Accessor>
inline float vdbDistance(const openvdb::math::Transform& xform, const Accessor& acc, const Decode& decode, float voxel,
                         const Eigen::Vector3f& p, Eigen::Vector3f& gradient)
{
    const openvdb::Vec3d x = xform.worldToIndex(openvdb::Vec3d(p.x(), p.y(), p.z()));
    const openvdb::Coord ijk = openvdb::Coord::floor(x);
    const openvdb::Vec3d uvw = x - ijk.asVec3d();
    float v[2][2][2];  // [x][y][z]
    openvdb::tools::BoxSampler::getValues(v, acc, ijk);
    if constexpr (std::is_same_v<typename Accessor::ValueType, uint16_t>)
        for (int n = 0; n < 8; ++n) v[n >> 2][(n >> 1) & 1][n & 1] = decode(uint16_t(v[n >> 2][(n >> 1) & 1][n & 1]));
    const float a = float(uvw.x()), b = float(uvw.y()), c = float(uvw.z());
    gradient.x() = (1 - b) * (1 - c) * (v[1][0][0] - v[0][0][0]) + b * (1 - c) * (v[1][1][0] - v[0][1][0]) +
                   (1 - b) * c * (v[1][0][1] - v[0][0][1]) + b * c * (v[1][1][1] - v[0][1][1]);
    gradient.y() = (1 - a) * (1 - c) * (v[0][1][0] - v[0][0][0]) + a * (1 - c) * (v[1][1][0] - v[1][0][0]) +
                   (1 - a) * c * (v[0][1][1] - v[0][0][1]) + a * c * (v[1][1][1] - v[1][0][1]);
    gradient.z() = (1 - a) * (1 - b) * (v[0][0][1] - v[0][0][0]) + a * (1 - b) * (v[1][0][1] - v[1][0][0]) +
                   (1 - a) * b * (v[0][1][1] - v[0][1][0]) + a * b * (v[1][1][1] - v[1][1][0]);
    gradient /= voxel;
    return openvdb::tools::BoxSampler::trilinearInterpolation(v, uvw);
}

template <class Query>
double nsPerQuery(const std::vector<Eigen::Vector3f>& queries, double& sum, Query&& query)
{
    sum = 0;
    const auto t = Clock::now();
    for (const auto& p : queries) sum += query(p);
    return seconds(t) * 1e9 / double(queries.size());
}

/** Maximum, mean and (kept values) quantiles of a non-negative quantity. */
struct Stats
{
    double max = 0, sum = 0;
    std::vector<float> values;
    void add(double x) { max = std::max(max, x), sum += x, values.push_back(float(x)); }
    size_t n() const { return values.size(); }
    double mean() const { return values.empty() ? 0 : sum / double(values.size()); }
    double quantile(double q)
    {
        if (values.empty()) return 0;
        const size_t k = std::min(values.size() - 1, size_t(q * double(values.size())));
        std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(k), values.end());
        return values[k];
    }
};

double angleDeg(const Eigen::Vector3f& a, const Eigen::Vector3f& b)
{
    return std::acos(std::clamp(double(a.dot(b)) / (double(a.norm()) * double(b.norm())), -1.0, 1.0)) * 180.0 / M_PI;
}

/** The accuracy rows (see the file comment). */
template <class Grid>
void check(const map::LidarMap& map, const Settings& s, const Grid& vdb, const Decode& decode,
           std::vector<Eigen::Vector3f> queries, const std::string& variant)
{
    map::DistanceFieldOptions o;
    o.voxel_m = s.voxel_m, o.max_distance_m = s.max_distance_m, o.margin_m = std::max(1.0, s.max_distance_m);
    o.layout = s.ours == "dense"    ? map::DistanceFieldLayout::Dense
               : s.ours == "sparse" ? map::DistanceFieldLayout::Sparse
                                    : map::DistanceFieldLayout::Auto;
    const map::DistanceField ours = map::DistanceField::build(map, o, s.map_file);
    const float voxel = ours.voxelSize(), truncation = ours.maxDistance();
    const Eigen::Vector3i dims = ours.dimensions();
    const auto oursVoxel = [&](const openvdb::Coord& c) {
        return c.x() >= 0 && c.y() >= 0 && c.z() >= 0 && c.x() < dims.x() && c.y() < dims.y() && c.z() < dims.z()
                   ? ours.voxel(c.x(), c.y(), c.z())
                   : truncation;
    };
    const MapCloud cloud{map};
    const KdTree kd(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));  // built here
    const auto nearest = [&](const Eigen::Vector3f& p) {
        uint32_t index = 0;
        float d2 = 0;
        kd.knnSearch(p.data(), 1, &index, &d2);
        return map.point(index);
    };
    const typename Grid::ConstAccessor acc = vdb.getConstAccessor();
    const openvdb::math::Transform& xform = vdb.transform();

    // The fields against each other at the queries whose cell lies wholly within the truncation in ours, and
    // against the exact distance (and direction) to the nearest map point there; both fields' voxel values against
    // the exact distance at the voxel nearest each query.
    struct FieldStats
    {
        Stats value, angle, voxel, voxel_near;
    } of_ours, of_vdb;
    Stats difference, difference_angle;
    size_t zero_gradient = 0;
    for (const Eigen::Vector3f& p : queries)
    {
        const Eigen::Vector3f gi = (p - ours.origin()) / voxel;
        const openvdb::Coord c(int(std::lround(gi.x())), int(std::lround(gi.y())), int(std::lround(gi.z())));
        const Eigen::Vector3f centre =
            ours.origin() + voxel * Eigen::Vector3f(float(c.x()), float(c.y()), float(c.z()));
        const float exact_c = std::min(truncation, (centre - nearest(centre)).norm());
        if (exact_c < truncation)
        {
            of_ours.voxel.add(std::abs(oursVoxel(c) - exact_c)),
                of_vdb.voxel.add(std::abs(decode(acc.getValue(c)) - exact_c));
            if (exact_c <= 2 * voxel)
                of_ours.voxel_near.add(std::abs(oursVoxel(c) - exact_c)),
                    of_vdb.voxel_near.add(std::abs(decode(acc.getValue(c)) - exact_c));
        }
        const openvdb::Coord lo = openvdb::Coord::floor(xform.worldToIndex(openvdb::Vec3d(p.x(), p.y(), p.z())));
        bool band = true;
        for (int corner = 0; corner < 8 && band; ++corner)
            band = oursVoxel(lo.offsetBy(corner & 1, (corner >> 1) & 1, corner >> 2)) < truncation;
        if (!band) continue;
        Eigen::Vector3f g_ours, g_vdb;
        const float d_ours = ours.distance(p, g_ours), d_vdb = vdbDistance(xform, acc, decode, voxel, p, g_vdb);
        const Eigen::Vector3f away = p - nearest(p);
        const float exact = std::min(truncation, away.norm());
        difference.add(std::abs(d_vdb - d_ours));
        of_ours.value.add(std::abs(d_ours - exact)), of_vdb.value.add(std::abs(d_vdb - exact));
        if (g_ours.norm() < 1e-6f || g_vdb.norm() < 1e-6f)
        {
            ++zero_gradient;
            continue;
        }
        difference_angle.add(angleDeg(g_ours, g_vdb));
        if (away.norm() > 1e-6f) of_ours.angle.add(angleDeg(g_ours, away)), of_vdb.angle.add(angleDeg(g_vdb, away));
    }
    // All the OpenVDB field's voxels against ours (ours at the truncation where OpenVDB has none).
    Stats all_voxels;
    for (auto v = vdb.tree().cbeginValueOn(); v; ++v)
    {
        const float d = std::abs(decode(*v) - oursVoxel(v.getCoord()));
        all_voxels.max = std::max(all_voxels.max, double(d)), all_voxels.sum += d;
    }
    const auto active = double(vdb.activeVoxelCount());

    // Query time of both fields, back to back in this process: at random (the order of the queries above), then in
    // a coherent order (sorted by 8^3-voxel block, as the points of one stereo frame are more nearly than random
    // map points).
    double sum_ours = 0, sum_vdb = 0, gradient_sum = 0;
    const auto timeBoth = [&](double& ns_ours, double& ns_vdb) {
        ns_ours = nsPerQuery(queries, sum_ours, [&](const Eigen::Vector3f& p) {
            Eigen::Vector3f g;
            const float d = ours.distance(p, g);
            gradient_sum += double(g.x());
            return d;
        });
        const typename Grid::ConstAccessor fresh = vdb.getConstAccessor();
        ns_vdb = nsPerQuery(queries, sum_vdb, [&](const Eigen::Vector3f& p) {
            Eigen::Vector3f g;
            const float d = vdbDistance(xform, fresh, decode, voxel, p, g);
            gradient_sum += double(g.x());
            return d;
        });
    };
    double random_ours = 0, random_vdb = 0, ns_ours = 0, ns_vdb = 0;
    timeBoth(random_ours, random_vdb);
    std::sort(queries.begin(), queries.end(), [&](const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
        const Eigen::Vector3i ka = ((a - ours.origin()) / (8 * voxel)).array().floor().cast<int>();
        const Eigen::Vector3i kb = ((b - ours.origin()) / (8 * voxel)).array().floor().cast<int>();
        return std::make_tuple(ka.z(), ka.y(), ka.x()) < std::make_tuple(kb.z(), kb.y(), kb.x());
    });
    timeBoth(ns_ours, ns_vdb);

    std::printf(
        "\n| map | OpenVDB field | band queries | value difference: max / mean | gradient angle: mean / "
        "median / p99 / max |\n|---|---|---|---|---|\n");
    std::printf("| %s | %s | %zu | %.4f / %.5f m | %.2f / %.2f / %.1f / %.1f deg |\n", s.map_file.c_str(),
                variant.c_str(), difference.n(), difference.max, difference.mean(), difference_angle.mean(),
                difference_angle.quantile(0.5), difference_angle.quantile(0.99), difference_angle.max);
    std::printf(
        "\n| map | field | value error at the queries: max / mean | gradient to the exact direction: "
        "mean / median / p99 | voxel error: max / mean | voxel error within 2 voxels: max / mean | query: "
        "random / coherent order |\n|---|---|---|---|---|---|---|\n");
    for (const bool is_ours : {true, false})
    {
        FieldStats& f = is_ours ? of_ours : of_vdb;
        std::printf(
            "| %s | %s | %.4f / %.5f m | %.2f / %.2f / %.1f deg | %.4f / %.5f m | %.4f / %.5f m | %.0f / %.0f ns |\n",
            s.map_file.c_str(), is_ours ? (ours.sparse() ? "ours, sparse" : "ours, dense") : variant.c_str(),
            f.value.max, f.value.mean(), f.angle.mean(), f.angle.quantile(0.5), f.angle.quantile(0.99), f.voxel.max,
            f.voxel.mean(), f.voxel_near.max, f.voxel_near.mean(), is_ours ? random_ours : random_vdb,
            is_ours ? ns_ours : ns_vdb);
    }
    std::fprintf(
        stderr,
        "check: %zu band queries (%zu with a zero gradient), %zu query voxels below the truncation (%zu within "
        "2 voxels); all %.0f OpenVDB voxels against ours: max %.4f mean %.5f m; coherent means %.4f %.4f "
        "(gradient sum %.3g)\n",
        difference.n(), zero_gradient, of_ours.voxel.n(), of_ours.voxel_near.n(), active, all_voxels.max,
        all_voxels.sum / std::max(1.0, active), sum_ours / double(queries.size()), sum_vdb / double(queries.size()),
        gradient_sum);
}

int usage()
{
    std::cerr
        << "usage: bench_distance_field_openvdb <map file> [--band N] [--sweeps N] [--threads N] [--values float|u16]"
           " [--voxel M] [--max-distance M] [--ours dense|sparse|auto] [--no-check]\n";
    return 2;
}

/** The queries' time, the table row, and the check (everything after the build). */
template <class Grid>
void report(const map::LidarMap& map, const Settings& s, const Grid& field, const Decode& decode, double build_s,
            double loaded_mb, const BuildTimes& times, const std::string& variant)
{
    const float voxel = float(s.voxel_m);
    // The queries of bench_distance_field (same generator, seed and expression).
    std::mt19937 rng(1);
    std::uniform_int_distribution<size_t> pick(0, map.size() - 1);
    std::uniform_real_distribution<float> jitter(-0.3f, 0.3f);
    std::vector<Eigen::Vector3f> queries;
    for (int q = 0; q < 1'000'000; ++q)
        queries.push_back(map.point(pick(rng)) + Eigen::Vector3f(jitter(rng), jitter(rng), jitter(rng)));

    const openvdb::math::Transform& xform = field.transform();
    double sum = 0, gradient_sum = 0;
    const typename Grid::ConstAccessor acc = field.getConstAccessor();  // one per querying thread
    const double ns = nsPerQuery(queries, sum, [&](const Eigen::Vector3f& p) {
        Eigen::Vector3f g;
        const float d = vdbDistance(xform, acc, decode, voxel, p, g);
        gradient_sum += double(g.x());
        return d;
    });
    const double peak_mb = peakResidentMb();

    // Other sampler paths of a FloatGrid, for reference: GridSampler (value only), BoxStencil (value and gradient).
    double ns_sampler = 0, ns_stencil = 0, sum_sampler = 0, sum_stencil = 0;
    if constexpr (std::is_same_v<Grid, FloatGrid>)
    {
        const openvdb::tools::GridSampler<typename Grid::ConstAccessor, openvdb::tools::BoxSampler> sampler(acc, xform);
        ns_sampler = nsPerQuery(queries, sum_sampler, [&](const Eigen::Vector3f& p) {
            return sampler.wsSample(openvdb::Vec3d(p.x(), p.y(), p.z()));
        });
        openvdb::math::BoxStencil<FloatGrid> stencil(field);
        ns_stencil = nsPerQuery(queries, sum_stencil, [&](const Eigen::Vector3f& p) {
            const openvdb::Vec3d x = xform.worldToIndex(openvdb::Vec3d(p.x(), p.y(), p.z()));
            stencil.moveTo(x);
            const openvdb::Vec3f xf(x);
            gradient_sum += double(stencil.gradient(xf).x());
            return stencil.interpolation(xf);
        });
    }

    const openvdb::Coord dim = field.evalActiveVoxelDim();
    std::printf("| %s | %zu | %s | %d x %d x %d | %.2f s | %.0f MB | %.0f MB | %.0f MB | %.0f ns | %.3f |\n",
                s.map_file.c_str(), map.size(), variant.c_str(), dim.x(), dim.y(), dim.z(), build_s,
                double(field.memUsage()) / 1048576.0, loaded_mb, peak_mb, ns, sum / double(queries.size()));
    std::fflush(stdout);
    std::fprintf(
        stderr,
        "openvdb %s: rasterise %.2f s, sweep %.2f s (%zu voxels solved, %zu fixed), compact %.2f s; %zu leaves, "
        "%llu active voxels; gradient sum %.3g",
        OPENVDB_LIBRARY_VERSION_STRING, times.raster, times.sweep, times.swept_voxels, times.boundary_voxels,
        times.compact, size_t(field.tree().leafCount()), static_cast<unsigned long long>(field.activeVoxelCount()),
        gradient_sum);
    if constexpr (std::is_same_v<Grid, FloatGrid>)
        std::fprintf(
            stderr, "; GridSampler::wsSample (value) %.0f ns, BoxStencil (value + gradient) %.0f ns, means %.4f %.4f",
            ns_sampler, ns_stencil, sum_sampler / double(queries.size()), sum_stencil / double(queries.size()));
    std::fprintf(stderr, "\n");
    if (s.check) check(map, s, field, decode, std::move(queries), variant);
}

}  // namespace

int main(int argc, char** argv)
{
    Settings s;
    for (int i = 1; i < argc; ++i)
    {
        const std::string a = argv[i];
        const bool has_value = i + 1 < argc;
        if (a == "--no-check")
            s.check = false;
        else if (a == "--band" && has_value)
            s.band = std::stoi(argv[++i]);
        else if (a == "--sweeps" && has_value)
            s.sweeps = std::stoi(argv[++i]);
        else if (a == "--threads" && has_value)
            s.threads = std::stoi(argv[++i]);
        else if (a == "--values" && has_value &&
                 (argv[i + 1] == std::string("float") || argv[i + 1] == std::string("u16")))
            s.u16 = argv[++i] == std::string("u16");
        else if (a == "--voxel" && has_value)
            s.voxel_m = std::stod(argv[++i]);
        else if (a == "--max-distance" && has_value)
            s.max_distance_m = std::stod(argv[++i]);
        else if (a == "--ours" && has_value)
            s.ours = argv[++i];
        else if (a.rfind("--", 0) != 0 && s.map_file.empty())
            s.map_file = a;
        else
            return usage();
    }
    if (s.map_file.empty() || s.band < 1 || s.sweeps < 1 || s.threads < 1 || !(s.voxel_m > 0) ||
        !(s.max_distance_m > 0))
        return usage();
    try
    {
        openvdb::initialize();
        tbb::global_control threads(tbb::global_control::max_allowed_parallelism, size_t(s.threads));
        const map::LidarMap map = map::LidarMap::load(s.map_file);
        const double loaded_mb = peakResidentMb();
        // Our voxels (DistanceField::build): centres at multiples of the voxel, the first at or below the map's
        // minimum less the margin (the bench's margin: max(1 m, truncation)).
        const float voxel = float(s.voxel_m), truncation = float(s.max_distance_m);
        const double margin = std::max(1.0, s.max_distance_m);
        const Eigen::Vector3f origin =
            (((map.bounds().min.cast<double>().array() - margin) / s.voxel_m).floor() * s.voxel_m)
                .matrix()
                .cast<float>();
        const Decode decode{truncation, truncation / 65535.f};

        const auto t0 = Clock::now();
        BuildTimes times;
        FloatGrid::Ptr field = buildVdbField(map, origin, voxel, truncation, s, times);
        U16Grid::Ptr field_u16;
        if (s.u16)
        {
            const auto t = Clock::now();
            field_u16 = toU16(*field, decode);
            field.reset();
            times.compact += seconds(t);
        }
        const double build_s = seconds(t0);

        const bool swept = s.band < int(std::ceil(truncation / voxel - 1e-4f));
        const std::string variant = "openvdb band " + std::to_string(s.band) +
                                    (swept ? " + sweep x" + std::to_string(s.sweeps) : std::string(" exact")) +
                                    (s.u16 ? ", 16-bit" : ", float") +
                                    (s.threads > 1 ? ", " + std::to_string(s.threads) + " threads" : std::string());
        if (s.u16)
            report(map, s, *field_u16, decode, build_s, loaded_mb, times, variant);
        else
            report(map, s, *field, decode, build_s, loaded_mb, times, variant);
        return 0;
    }
    catch (const std::exception& e)
    {
        std::cerr << "bench_distance_field_openvdb: error: " << e.what() << "\n";
        return 1;
    }
}
