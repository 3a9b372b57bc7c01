// Sampling the surfaces of a Gaussian-mixture map (see gmm_surface.h).
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <optional>
#include <quasiloc/core/error.h>
#include <quasiloc/map/gmm_surface.h>
#include <quasiloc/map/map_import.h>
#include <random>
#include <sstream>

namespace quasiloc::map
{
namespace
{
constexpr double kMaxCellsPerComponent = 1e8;

std::string num(double v)
{
    std::ostringstream s;
    s << v;
    return s.str();
}

void requireIn(double v, double lo, double hi, const std::string& key_prefix, const std::string& key)
{
    core::require(std::isfinite(v) && v >= lo && v <= hi, key_prefix + key,
                  "must be within [" + num(lo) + ", " + num(hi) + "], got " + num(v));
}

/** One jittered point per grid cell of the ellipse's bounding rectangle, kept when inside the ellipse. */
void sampleEllipse(const GmmComponentSurface& s, double spacing_m, float reflectivity, std::mt19937_64& rng,
                   LidarMap& out)
{
    const double a = s.semi_u_m, b = s.semi_v_m;
    if (!(a > 0 && b > 0)) return;
    const long nu = std::max(1L, static_cast<long>(std::ceil(2 * a / spacing_m)));
    const long nv = std::max(1L, static_cast<long>(std::ceil(2 * b / spacing_m)));
    const double u0 = -0.5 * nu * spacing_m, v0 = -0.5 * nv * spacing_m;
    std::uniform_real_distribution<double> jitter(0.0, 1.0);
    for (long i = 0; i < nu; ++i)
        for (long j = 0; j < nv; ++j)
        {
            const double u = u0 + (i + jitter(rng)) * spacing_m;
            const double v = v0 + (j + jitter(rng)) * spacing_m;
            if ((u / a) * (u / a) + (v / b) * (v / b) > 1.0) continue;
            const Eigen::Vector3d p = s.center + u * s.axis_u + v * s.axis_v;
            out.addPoint(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()), reflectivity);
        }
}
}  // namespace

void GmmSurfaceOptions::check(const std::string& key_prefix) const
{
    requireIn(density_per_m2, 1.0, 1e6, key_prefix, "density_per_m2");
    requireIn(truncation_sigma, 0.1, 5.0, key_prefix, "truncation_sigma");
    requireIn(max_flatness, 0.0, 1.0, key_prefix, "max_flatness");
    requireIn(reflectivity, 0.0, 1.0, key_prefix, "reflectivity");
}

double GmmComponentSurface::areaM2() const { return M_PI * semi_u_m * semi_v_m; }

GmmComponentSurface componentSurface(const GmmComponent& c, double truncation_sigma)
{
    const Eigen::Matrix3d sym = 0.5 * (c.covariance + c.covariance.transpose());
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(sym);
    const Eigen::Vector3d ev = es.eigenvalues().cwiseMax(0.0);  // ascending
    GmmComponentSurface s;
    s.center = c.mean;
    s.normal = es.eigenvectors().col(0);
    s.axis_v = es.eigenvectors().col(1);
    s.axis_u = es.eigenvectors().col(2);
    s.sigmas = ev.cwiseSqrt();
    s.semi_u_m = truncation_sigma * s.sigmas[2];
    s.semi_v_m = truncation_sigma * s.sigmas[1];
    s.flatness = s.sigmas[1] > 0 ? s.sigmas[0] / s.sigmas[1] : std::numeric_limits<double>::infinity();
    return s;
}

LidarMap sampleGmmSurfaces(const std::vector<GmmComponent>& components, const GmmSurfaceOptions& options,
                           GmmSurfaceStats* stats_out, const std::string& input)
{
    options.check(input + " option ");
    const double spacing_m = 1.0 / std::sqrt(options.density_per_m2);
    const auto reflectivity = static_cast<float>(options.reflectivity);
    GmmSurfaceStats st;
    st.components = components.size();
    std::vector<GmmComponentSurface> surfaces;
    surfaces.reserve(components.size());
    double expected_points = 0;
    for (size_t k = 0; k < components.size(); ++k)
    {
        const GmmComponentSurface s = componentSurface(components[k], options.truncation_sigma);
        const double cells = std::ceil(2 * s.semi_u_m / spacing_m) * std::ceil(2 * s.semi_v_m / spacing_m);
        core::require(cells <= kMaxCellsPerComponent, input + " (component " + std::to_string(k) + ")",
                      "surface of " + num(s.areaM2()) + " m2 needs " + num(cells) + " grid cells at " +
                          num(options.density_per_m2) + " points/m2 (limit " + num(kMaxCellsPerComponent) + ")");
        surfaces.push_back(s);
        if (s.flatness <= options.max_flatness) expected_points += options.density_per_m2 * s.areaM2();
    }
    LidarMap map;
    map.reserve(static_cast<size_t>(expected_points * 1.01) + 16);
    for (size_t k = 0; k < components.size(); ++k)
    {
        if (components[k].is_degenerated) ++st.degenerated;
        const GmmComponentSurface& s = surfaces[k];
        if (s.flatness > options.max_flatness)
        {
            ++st.skipped_not_flat;
            continue;
        }
        ++st.sampled;
        st.area_m2 += s.areaM2();
        std::seed_seq seq{static_cast<uint32_t>(options.seed), static_cast<uint32_t>(options.seed >> 32),
                          static_cast<uint32_t>(k), static_cast<uint32_t>(static_cast<uint64_t>(k) >> 32)};
        std::mt19937_64 rng(seq);
        sampleEllipse(s, spacing_m, reflectivity, rng, map);
    }
    st.points = map.size();
    if (stats_out) *stats_out = st;
    return map;
}

GmmImportResult importGmm(const std::string& path, const GmmSurfaceOptions& options, double voxel_size_m,
                          mrpt::system::CTimeLogger* timer)
{
    core::require(voxel_size_m >= 0 && std::isfinite(voxel_size_m), "voxel_size_m",
                  "must be >= 0 (0 = no downsampling), got " + num(voxel_size_m));
    auto stage = [timer](const char* name) {
        return timer ? std::make_optional<mrpt::system::CTimeLoggerEntry>(*timer, name) : std::nullopt;
    };
    GmmImportResult r;
    std::vector<GmmComponent> components;
    {
        const auto t = stage("import.read");
        components = readGmmFile(path);
    }
    {
        const auto t = stage("import.sample");
        r.map = sampleGmmSurfaces(components, options, &r.stats, path);
    }
    r.points_sampled = r.map.size();
    core::require(!r.map.empty(), path, "no component yielded a point (all skipped as not flat, or too small)");
    if (voxel_size_m > 0)
    {
        const auto t = stage("import.voxel");
        r.map = voxelDownsample(r.map, voxel_size_m);
    }
    return r;
}

}  // namespace quasiloc::map
