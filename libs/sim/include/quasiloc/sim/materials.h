#pragma once
// Materials of the simulated world: what a camera sees (albedo texture) and what a LiDAR measures
// (intrinsic reflectivity texture), deliberately correlated but NOT equal.
//
// Every material is built from three tileable procedural layers (all deterministic for a seed):
//   shared  - structure both sensors see (panels, seams, wood grain, folds, checker squares),
//   camera  - detail of the visible spectrum only (print, paint, dirt, text on posters),
//   lidar   - detail of the near-infrared only (retro-reflective tape, IR-absorbing dye, moisture).
//   albedo       = clamp(a0 + a_shared * shared + a_camera * camera)
//   reflectivity = clamp(r0 + r_shared * shared' + r_lidar * lidar + own noise) ^ r_gamma
// where shared' is the shared layer through a per-material non-linear (sometimes inverting) response.
// The LiDAR's range and incidence falloff and its noise are added by the sampler, not here.
//
// No texture depends on files: everything is procedural, so the simulator runs anywhere.
// Texture coordinates are metres along the surface; a material tile covers `tile_size_m` metres.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace quasiloc::sim
{
enum MaterialId : uint16_t
{
    kWallPlaster = 0,
    kFloorCarpet,
    kCeilingPanels,
    kWoodPanel,
    kPoster,
    kMattress,
    kCardboard,
    kMetalPole,
    kCurtain,
    kCheckerBoard,
    kConcrete,
    kPersonClothes,
    kAsphalt,    ///< outdoor road surface
    kRoadPaint,  ///< road markings: white paint with retro-reflective beads (bright at 905 nm)
    kGlass,      ///< windows: the camera sees a dark pane, the LiDAR gets no return (lidar_sweeps.h)
    kFoliage,    ///< tree crowns
    kBark,       ///< tree trunks
    kCarPaint,   ///< car bodies
    kNumMaterials
};

class Material
{
   public:
    std::string name;
    float tile_size_m = 1;
    int size_px = 0;                   ///< level-0 texture side (power of two)
    std::vector<cv::Mat> albedo_mips;  ///< CV_8UC1, level 0 .. log2(size_px); albedo * 255
    cv::Mat reflectivity;              ///< CV_32FC1, size_px x size_px, intrinsic reflectivity [0,1]

    /** Bilinear albedo in [0,1] at texture coordinates uv (metres), mip level chosen from the footprint of
     *  one pixel on the surface (metres). */
    inline float albedo(const Eigen::Vector2f& uv_m, float footprint_m) const;
    /** Bilinear intrinsic reflectivity in [0,1]. */
    float intrinsicReflectivity(const Eigen::Vector2f& uv_m) const;
    /** Mean albedo and reflectivity over the tile (for tests and statistics). */
    double meanAlbedo() const;
};

struct MaterialLibrary
{
    std::vector<Material> materials;  ///< indexed by MaterialId
    const Material& operator[](size_t id) const { return materials[id]; }
    size_t size() const { return materials.size(); }
};

/** Builds every MaterialId material; texture_size_px must be a power of two in [32, 2048]. */
MaterialLibrary makeProceduralMaterials(uint64_t seed, int texture_size_px = 512);

/** Which materials a world gets ([World] materials):
 *  procedural: the recipes above (albedo and reflectivity share a structure layer by design);
 *  spectral:   the same camera textures at the visible albedo of real surfaces, the NIR reflectivity at their
 *              ~905 nm reflectance with its own texture (spectral_materials.h). */
enum class MaterialSet
{
    procedural,
    spectral
};

/** The library of `set` (same seeds, texture sizes and camera patterns in both). */
MaterialLibrary makeMaterials(MaterialSet set, uint64_t seed, int texture_size_px = 512);

/** Bilinear lookup with wrap-around of a square power-of-two texture; u, v in texels (texel centres at
 *  integers). Inline: the renderer calls it once per pixel. */
template <typename T>
inline float bilinearWrap(const cv::Mat& tex, float u, float v)
{
    const int mask = tex.cols - 1;
    const float fu = std::floor(u), fv = std::floor(v);
    const float tu = u - fu, tv = v - fv;
    const int x0 = static_cast<int>(fu) & mask, y0 = static_cast<int>(fv) & mask;
    const int x1 = (x0 + 1) & mask, y1 = (y0 + 1) & mask;
    const T* r0 = tex.ptr<T>(y0);
    const T* r1 = tex.ptr<T>(y1);
    const float a = static_cast<float>(r0[x0]) + (static_cast<float>(r0[x1]) - static_cast<float>(r0[x0])) * tu;
    const float b = static_cast<float>(r1[x0]) + (static_cast<float>(r1[x1]) - static_cast<float>(r1[x0])) * tu;
    return a + (b - a) * tv;
}

float Material::albedo(const Eigen::Vector2f& uv_m, float footprint_m) const
{
    const float texels_per_m = size_px / tile_size_m;
    int level = 0;
    const float texels_per_pixel = footprint_m * texels_per_m;
    if (texels_per_pixel >= 2.f)  // exponent of the float = floor(log2), without calling log2
        level = std::min(static_cast<int>(albedo_mips.size()) - 1, std::ilogb(texels_per_pixel));
    const float scale = texels_per_m / static_cast<float>(1 << level);
    return bilinearWrap<uint8_t>(albedo_mips[level], uv_m.x() * scale - 0.5f, uv_m.y() * scale - 0.5f) * (1.f / 255.f);
}

}  // namespace quasiloc::sim
