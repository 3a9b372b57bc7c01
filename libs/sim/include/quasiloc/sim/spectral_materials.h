#pragma once
// The "spectral" material set ([World] materials = spectral): each material's mean visible albedo (what the camera
// sees) and mean near-infrared reflectance at the LiDAR's wavelength (~905 nm) are levels of real surfaces from
// published spectral data (docs/crossmodal_statistics.md lists the sources), and the two textures are related only
// as far as the material's physics relates them:
//   albedo       = the procedural camera texture (materials.cpp) scaled to mean visible_albedo;
//   reflectivity = nir_reflectance * (1 + nir_variation * (coupling * Z_visible + sqrt(1 - coupling^2) * Z_nir)),
// Z_visible the standardised camera texture, Z_nir the standardised NIR-only detail of the procedural material (its
// LiDAR layer and speckle). coupling is the within-material correlation of the two textures: high where one pigment
// darkens both bands (carbon-black toner of a calibration board), near zero where the visible pattern is a dye or
// ink that is transparent in the near infrared (prints, dyed fabrics), moderate where dirt, moisture or seams darken
// both. The camera's lighting and the LiDAR's range and incidence falloff come on top (renderer, sampler).
#include <cstdint>

namespace quasiloc::sim
{
struct SpectralMaterial
{
    float visible_albedo = 0;     ///< mean albedo over the visible band (camera), [0, 1]
    float nir_reflectance = 0;    ///< mean reflectance at ~905 nm (LiDAR), [0, 1]
    float nir_variation = 0;      ///< relative standard deviation of the NIR texture
    float coupling = 0;           ///< correlation of the NIR texture with the visible one, [-1, 1]
    const char* stands_for = "";  ///< the real surface whose levels are taken
};

/** The spectral levels of a MaterialId (materials.h); InputError for an id outside it. */
const SpectralMaterial& spectralMaterial(uint16_t material);

}  // namespace quasiloc::sim
