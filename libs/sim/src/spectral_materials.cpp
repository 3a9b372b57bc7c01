#include <quasiloc/core/error.h>
#include <quasiloc/sim/materials.h>
#include <quasiloc/sim/spectral_materials.h>
#include <string>

namespace quasiloc::sim
{
namespace
{
// Indexed by MaterialId. Levels: docs/crossmodal_statistics.md, table "Spectral levels", with their sources.
const SpectralMaterial kSpectral[kNumMaterials] = {
    /* kWallPlaster    */ {0.75f, 0.80f, 0.10f, 0.30f, "white gypsum plaster / white interior paint"},
    /* kFloorCarpet    */ {0.12f, 0.45f, 0.25f, 0.00f, "dark dyed synthetic floor covering (dye transparent in NIR)"},
    /* kCeilingPanels  */ {0.78f, 0.80f, 0.08f, 0.40f, "white mineral-fibre ceiling tile"},
    /* kWoodPanel      */ {0.40f, 0.60f, 0.12f, 0.20f, "light wood (pine, plywood)"},
    /* kPoster         */ {0.65f, 0.80f, 0.08f, 0.20f, "white paper with colour print (inks transparent in NIR)"},
    /* kMattress       */ {0.30f, 0.60f, 0.15f, 0.00f, "dyed fabric cover"},
    /* kCardboard      */ {0.35f, 0.65f, 0.12f, 0.10f, "brown kraft cardboard with print"},
    /* kMetalPole      */ {0.30f, 0.45f, 0.60f, 0.00f, "painted steel with retro-reflective tape"},
    /* kCurtain        */ {0.05f, 0.55f, 0.20f, 0.00f, "black dyed fabric (dye transparent in NIR)"},
    /* kCheckerBoard   */ {0.45f, 0.45f, 0.90f, 0.95f, "white board, black carbon toner squares"},
    /* kConcrete       */ {0.30f, 0.38f, 0.15f, 0.50f, "grey construction concrete"},
    /* kPersonClothes  */ {0.25f, 0.55f, 0.20f, 0.00f, "dyed cotton clothing"},
    /* kAsphalt        */ {0.08f, 0.12f, 0.20f, 0.40f, "weathered asphalt road surface"},
    /* kRoadPaint      */ {0.70f, 0.85f, 0.08f, 0.30f, "white road paint with retro-reflective glass beads"},
    /* kGlass          */ {0.10f, 0.05f, 0.10f, 0.30f, "window glass (the LiDAR's return is dropped)"},
    /* kFoliage        */ {0.08f, 0.50f, 0.25f, -0.30f, "green leaves (chlorophyll: dark in red, bright at 905 nm)"},
    /* kBark           */ {0.15f, 0.30f, 0.15f, 0.40f, "tree bark"},
    /* kCarPaint       */ {0.30f, 0.45f, 0.10f, 0.40f, "car body paint"},
};
}  // namespace

const SpectralMaterial& spectralMaterial(uint16_t material)
{
    core::require(material < kNumMaterials, "material id", "no material " + std::to_string(material));
    return kSpectral[material];
}

}  // namespace quasiloc::sim
