#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/sim/materials.h>
#include <quasiloc/sim/spectral_materials.h>
#include <random>

namespace quasiloc::sim
{
namespace
{
using Rng = std::mt19937_64;

float uniform01(Rng& rng) { return std::uniform_real_distribution<float>(0.f, 1.f)(rng); }

/** Tileable value noise: a cells x cells random lattice, quintic interpolation, wrap-around. */
cv::Mat periodicNoise(int n, int cells, Rng& rng)
{
    std::vector<float> lattice(static_cast<size_t>(cells) * cells);
    for (float& v : lattice) v = uniform01(rng);
    cv::Mat out(n, n, CV_32F);
    const float scale = static_cast<float>(cells) / n;
    auto fade = [](float t) { return t * t * t * (t * (t * 6 - 15) + 10); };
    for (int y = 0; y < n; ++y)
    {
        const float fy = y * scale;
        const int y0 = static_cast<int>(fy) % cells, y1 = (y0 + 1) % cells;
        const float ty = fade(fy - std::floor(fy));
        float* row = out.ptr<float>(y);
        for (int x = 0; x < n; ++x)
        {
            const float fx = x * scale;
            const int x0 = static_cast<int>(fx) % cells, x1 = (x0 + 1) % cells;
            const float tx = fade(fx - std::floor(fx));
            const float a = lattice[y0 * cells + x0], b = lattice[y0 * cells + x1];
            const float c = lattice[y1 * cells + x0], d = lattice[y1 * cells + x1];
            row[x] = (a + (b - a) * tx) * (1 - ty) + (c + (d - c) * tx) * ty;
        }
    }
    return out;
}

/** Gaussian blur of a tileable texture (OpenCV filters have no wrap-around border). */
void blurWrap(cv::Mat& m, double sigma)
{
    const int pad = static_cast<int>(std::ceil(4 * sigma)) + 1;
    cv::Mat padded, blurred;
    cv::copyMakeBorder(m, padded, pad, pad, pad, pad, cv::BORDER_WRAP);
    cv::GaussianBlur(padded, blurred, cv::Size(0, 0), sigma, sigma);
    m = blurred(cv::Rect(pad, pad, m.cols, m.rows)).clone();
}

/** Normalises to [0, 1] by min/max. */
cv::Mat normalised(const cv::Mat& m)
{
    double lo, hi;
    cv::minMaxLoc(m, &lo, &hi);
    cv::Mat out;
    m.convertTo(out, CV_32F, hi > lo ? 1.0 / (hi - lo) : 0.0, hi > lo ? -lo / (hi - lo) : 0.0);
    return out;
}

/** Fractal sum of octaves of periodic noise starting at base_cells lattice cells per tile. */
cv::Mat fbm(int n, int base_cells, int octaves, float persistence, Rng& rng)
{
    cv::Mat sum = cv::Mat::zeros(n, n, CV_32F);
    float amp = 1;
    for (int o = 0, cells = base_cells; o < octaves && cells <= n; ++o, cells *= 2, amp *= persistence)
        sum += amp * periodicNoise(n, cells, rng);
    return normalised(sum);
}

/** 1 on a grid of seam lines (period n/count, width px), 0 elsewhere; rows offset by half for bricks. */
cv::Mat seams(int n, int count_x, int count_y, int width_px, bool brick_offset)
{
    cv::Mat out = cv::Mat::zeros(n, n, CV_32F);
    const int px = n / count_x, py = n / count_y;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
        {
            const int row = y / py;
            const int xs = brick_offset && (row % 2) ? (x + px / 2) % n : x;
            if (y % py < width_px || xs % px < width_px) out.at<float>(y, x) = 1;
        }
    blurWrap(out, 0.8);
    return out;
}

/** Random axis-aligned rectangles and strokes, like print on a poster or a box (camera-only detail). */
cv::Mat printPattern(int n, int count, Rng& rng)
{
    cv::Mat out = cv::Mat::zeros(n, n, CV_32F);
    for (int i = 0; i < count; ++i)
    {
        const int x = static_cast<int>(uniform01(rng) * n), y = static_cast<int>(uniform01(rng) * n);
        const int w = 2 + static_cast<int>(uniform01(rng) * n / 6), h = 2 + static_cast<int>(uniform01(rng) * n / 24);
        const float v = 0.3f + 0.7f * uniform01(rng);
        cv::rectangle(out, cv::Rect(x, y, std::min(w, n - x), std::min(h, n - y)), cv::Scalar(v), cv::FILLED);
        if (uniform01(rng) < 0.3f)
            cv::circle(out, {x, y}, 3 + static_cast<int>(uniform01(rng) * n / 10), cv::Scalar(1 - v), 2, cv::LINE_AA);
    }
    return out;
}

cv::Mat checker(int n, int squares)
{
    cv::Mat out(n, n, CV_32F);
    const int s = n / squares;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) out.at<float>(y, x) = ((x / s + y / s) % 2) ? 1.f : 0.f;
    return out;
}

/** Wood grain: warped stripes along x. */
cv::Mat woodGrain(int n, Rng& rng)
{
    const cv::Mat warp = fbm(n, 4, 4, 0.5f, rng);
    cv::Mat out(n, n, CV_32F);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
        {
            const float s = std::sin(2.f * static_cast<float>(CV_PI) * (12.f * y / n + 2.5f * warp.at<float>(y, x)));
            out.at<float>(y, x) = 0.5f + 0.5f * s;
        }
    return out;
}

/** Diamond quilting of a mattress. */
cv::Mat quilting(int n, int count)
{
    cv::Mat out(n, n, CV_32F);
    const float k = 2.f * static_cast<float>(CV_PI) * count / n;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
        {
            const float a = std::abs(std::sin(0.5f * k * (x + y))), b = std::abs(std::sin(0.5f * k * (x - y)));
            out.at<float>(y, x) = std::pow(std::min(a, b), 0.4f);
        }
    return out;
}

/** Horizontal stripes (tape on a pole, folds of a curtain). */
cv::Mat stripes(int n, int count, float duty)
{
    cv::Mat out(n, n, CV_32F);
    for (int y = 0; y < n; ++y)
    {
        const float phase = std::fmod(static_cast<float>(y) * count / n, 1.f);
        out.row(y).setTo(phase < duty ? 1.f : 0.f);
    }
    blurWrap(out, 1.0);
    return out;
}

cv::Mat folds(int n, int count, Rng& rng)
{
    const cv::Mat warp = fbm(n, 2, 3, 0.5f, rng);
    cv::Mat out(n, n, CV_32F);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            out.at<float>(y, x) = 0.5f + 0.5f * std::sin(2.f * static_cast<float>(CV_PI) *
                                                         (count * x / float(n) + 0.7f * warp.at<float>(y, x)));
    return out;
}

/** How the layers combine in each modality (see materials.h). */
struct Recipe
{
    float a0, a_shared, a_camera;
    float r0, r_shared, r_lidar, r_noise, r_gamma;
    bool r_invert_shared;  ///< the NIR response of the shared structure is inverted (e.g. dark dye)
};

struct Layers
{
    cv::Mat shared, camera, lidar;
    Recipe recipe;
    float tile_size_m;
    std::string name;
};

Layers makeLayers(MaterialId id, int n, Rng& rng)
{
    auto noise = [&](int cells, int oct) { return fbm(n, cells, oct, 0.55f, rng); };
    switch (id)
    {
        case kWallPlaster:
            return {0.6f * noise(4, 3) + 0.4f * seams(n, 2, 1, 3, false),           noise(16, 5), noise(8, 4),
                    {0.55f, 0.25f, 0.25f, 0.55f, 0.15f, 0.30f, 0.08f, 1.0f, false}, 2.4f,         "wall_plaster"};
        case kFloorCarpet:
            return {seams(n, 2, 2, 2, false),
                    noise(64, 3),
                    noise(4, 4),
                    {0.18f, -0.10f, 0.35f, 0.30f, 0.10f, 0.35f, 0.10f, 1.2f, true},
                    1.0f,
                    "floor_carpet"};
        case kCeilingPanels:
            return {seams(n, 2, 2, 4, false),
                    noise(32, 4),
                    noise(4, 3),
                    {0.75f, -0.45f, 0.15f, 0.60f, 0.10f, 0.25f, 0.06f, 1.0f, false},
                    1.2f,
                    "ceiling_panels"};
        case kWoodPanel:
            return {woodGrain(n, rng),
                    noise(32, 4),
                    noise(2, 3),
                    {0.30f, 0.25f, 0.15f, 0.45f, 0.10f, 0.40f, 0.08f, 1.3f, true},
                    1.0f,
                    "wood_panel"};
        case kPoster:
            return {noise(2, 2), printPattern(n, 90, rng),
                    noise(8, 3), {0.80f, 0.05f, -0.70f, 0.70f, 0.10f, 0.15f, 0.05f, 1.0f, false},
                    1.0f,        "poster"};
        case kMattress:
            return {quilting(n, 8), noise(8, 4),
                    noise(16, 3),   {0.25f, 0.35f, 0.25f, 0.25f, 0.25f, 0.30f, 0.10f, 0.8f, false},
                    1.0f,           "mattress"};
        case kCardboard:
            return {stripes(n, 3, 0.12f),
                    printPattern(n, 25, rng),
                    noise(16, 4),
                    {0.45f, 0.25f, -0.30f, 0.50f, -0.20f, 0.30f, 0.08f, 1.0f, false},
                    0.8f,
                    "cardboard"};
        case kMetalPole:
            return {noise(8, 3),
                    noise(32, 4),
                    stripes(n, 6, 0.25f),
                    {0.15f, 0.15f, 0.10f, 0.20f, 0.05f, 0.70f, 0.05f, 1.0f, false},
                    0.6f,
                    "metal_pole_tape"};
        case kCurtain:
            return {folds(n, 10, rng),
                    noise(32, 3),
                    noise(4, 3),
                    {0.08f, 0.10f, 0.06f, 0.35f, 0.15f, 0.35f, 0.10f, 1.0f, true},
                    2.0f,
                    "black_curtain"};
        case kCheckerBoard:
            return {checker(n, 8), noise(16, 3),
                    noise(8, 3),   {0.08f, 0.82f, 0.05f, 0.35f, 0.35f, 0.15f, 0.05f, 1.0f, false},
                    0.8f,          "checker_board"};
        case kConcrete:
            return {noise(8, 5), noise(64, 3),
                    noise(4, 4), {0.35f, 0.30f, 0.15f, 0.40f, 0.20f, 0.30f, 0.12f, 1.1f, false},
                    2.0f,        "concrete"};
        case kAsphalt:
            return {noise(16, 5), noise(128, 3),
                    noise(8, 4),  {0.12f, 0.20f, 0.10f, 0.12f, 0.15f, 0.15f, 0.10f, 1.0f, false},
                    2.0f,         "asphalt"};
        case kRoadPaint:
            return {noise(8, 3),  noise(64, 3),
                    noise(16, 3), {0.75f, 0.15f, 0.10f, 0.80f, 0.10f, 0.20f, 0.05f, 1.0f, false},
                    1.0f,         "road_paint"};
        case kGlass:
            return {noise(2, 3), noise(32, 3),
                    noise(4, 3), {0.10f, 0.15f, 0.10f, 0.05f, 0.05f, 0.05f, 0.02f, 1.0f, false},
                    2.0f,        "window_glass"};
        case kFoliage:
            return {noise(32, 4), noise(64, 3),
                    noise(16, 3), {0.12f, 0.25f, 0.15f, 0.45f, 0.20f, 0.30f, 0.15f, 1.0f, false},
                    1.5f,         "foliage"};
        case kBark:
            return {stripes(n, 12, 0.4f),
                    noise(32, 4),
                    noise(8, 3),
                    {0.15f, 0.20f, 0.10f, 0.35f, 0.15f, 0.25f, 0.08f, 1.0f, false},
                    0.5f,
                    "bark"};
        case kCarPaint:
            return {noise(4, 3), noise(32, 3),
                    noise(8, 3), {0.30f, 0.30f, 0.10f, 0.40f, 0.20f, 0.20f, 0.08f, 1.0f, false},
                    2.0f,        "car_paint"};
        case kPersonClothes:
        default:
            return {stripes(n, 5, 0.5f),
                    noise(16, 4),
                    noise(8, 3),
                    {0.20f, 0.40f, 0.15f, 0.50f, 0.05f, 0.30f, 0.10f, 1.0f, false},
                    1.0f,
                    "person_clothes"};
    }
}

/** Mean and standard deviation of a CV_32F texture. */
std::pair<float, float> meanStd(const cv::Mat& m)
{
    cv::Scalar mean, stddev;
    cv::meanStdDev(m, mean, stddev);
    return {static_cast<float>(mean[0]), static_cast<float>(stddev[0])};
}

/** The spectral set's textures (spectral_materials.h) from the procedural camera texture and NIR-only detail. */
void spectralTextures(const SpectralMaterial& sp, const Recipe& r, const Layers& l, const cv::Mat& own_noise,
                      cv::Mat& albedo, cv::Mat& refl)
{
    const int n = albedo.rows;
    cv::Mat nir_detail(n, n, CV_32F);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            nir_detail.at<float>(y, x) =
                r.r_lidar * (l.lidar.at<float>(y, x) - 0.5f) + r.r_noise * (own_noise.at<float>(y, x) - 0.5f);
    const auto [a_mean, a_std] = meanStd(albedo);
    const auto [d_mean, d_std] = meanStd(nir_detail);
    const float own = std::sqrt(std::max(0.f, 1.f - sp.coupling * sp.coupling));
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
        {
            float& a = albedo.at<float>(y, x);
            const float z_vis = a_std > 0 ? (a - a_mean) / a_std : 0.f;
            const float z_nir = d_std > 0 ? (nir_detail.at<float>(y, x) - d_mean) / d_std : 0.f;
            refl.at<float>(y, x) = std::clamp(
                sp.nir_reflectance * (1 + sp.nir_variation * (sp.coupling * z_vis + own * z_nir)), 0.01f, 1.f);
            a = std::clamp(a * sp.visible_albedo / std::max(a_mean, 1e-3f), 0.02f, 0.98f);
        }
}

Material buildMaterial(const Layers& l, int n, Rng& rng, const SpectralMaterial* spectral)
{
    const Recipe& r = l.recipe;
    Material m;
    m.name = l.name;
    m.tile_size_m = l.tile_size_m;
    m.size_px = n;
    const cv::Mat own_noise = fbm(n, 64, 3, 0.6f, rng);  // speckle of the LiDAR return, its own pattern
    cv::Mat albedo(n, n, CV_32F), refl(n, n, CV_32F);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
        {
            const float s = l.shared.at<float>(y, x), c = l.camera.at<float>(y, x), d = l.lidar.at<float>(y, x);
            albedo.at<float>(y, x) = std::clamp(r.a0 + r.a_shared * s + r.a_camera * c, 0.02f, 0.98f);
            // Non-linear NIR response of the shared structure: a smooth step, optionally inverted.
            float sn = s * s * (3 - 2 * s);
            if (r.r_invert_shared) sn = 1 - sn;
            const float raw =
                r.r0 + r.r_shared * sn + r.r_lidar * (d - 0.5f) + r.r_noise * (own_noise.at<float>(y, x) - 0.5f);
            refl.at<float>(y, x) = std::pow(std::clamp(raw, 0.01f, 1.f), r.r_gamma);
        }
    if (spectral) spectralTextures(*spectral, r, l, own_noise, albedo, refl);
    m.reflectivity = refl;
    cv::Mat level;
    albedo.convertTo(level, CV_8U, 255.0);
    m.albedo_mips.push_back(level);
    while (level.cols > 1)
    {
        cv::Mat next;
        cv::resize(level, next, cv::Size(level.cols / 2, level.rows / 2), 0, 0, cv::INTER_AREA);
        m.albedo_mips.push_back(next);
        level = next;
    }
    return m;
}

}  // namespace

float Material::intrinsicReflectivity(const Eigen::Vector2f& uv_m) const
{
    const float scale = size_px / tile_size_m;
    return bilinearWrap<float>(reflectivity, uv_m.x() * scale - 0.5f, uv_m.y() * scale - 0.5f);
}

double Material::meanAlbedo() const { return cv::mean(albedo_mips[0])[0] / 255.0; }

MaterialLibrary makeProceduralMaterials(uint64_t seed, int texture_size_px)
{
    return makeMaterials(MaterialSet::procedural, seed, texture_size_px);
}

MaterialLibrary makeMaterials(MaterialSet set, uint64_t seed, int texture_size_px)
{
    const bool pow2 =
        texture_size_px >= 32 && texture_size_px <= 2048 && (texture_size_px & (texture_size_px - 1)) == 0;
    core::require(pow2, "texture_size_px",
                  "must be a power of two in [32, 2048], got " + std::to_string(texture_size_px));
    MaterialLibrary lib;
    for (int id = 0; id < kNumMaterials; ++id)
    {
        Rng rng(seed * 1000003ull + static_cast<uint64_t>(id) * 7919ull + 17ull);
        const Layers layers = makeLayers(static_cast<MaterialId>(id), texture_size_px, rng);
        const SpectralMaterial* spectral = set == MaterialSet::spectral ? &spectralMaterial(uint16_t(id)) : nullptr;
        lib.materials.push_back(buildMaterial(layers, texture_size_px, rng, spectral));
    }
    return lib;
}

}  // namespace quasiloc::sim
