#include <quasiloc/sim/surface_class.h>

namespace quasiloc::sim
{
const char* toString(SurfaceClass c)
{
    switch (c)
    {
        case SurfaceClass::road: return "road";
        case SurfaceClass::marking: return "marking";
        case SurfaceClass::facade: return "facade";
        case SurfaceClass::vegetation: return "vegetation";
        case SurfaceClass::vehicle: return "vehicle";
        default: return "other";
    }
}

SurfaceClass surfaceClassOf(uint16_t material)
{
    switch (material)
    {
        case kFloorCarpet:
        case kAsphalt: return SurfaceClass::road;
        case kRoadPaint:
        case kPoster:
        case kCheckerBoard: return SurfaceClass::marking;
        case kWallPlaster:
        case kCeilingPanels:
        case kWoodPanel:
        case kCurtain:
        case kGlass:
        case kConcrete: return SurfaceClass::facade;
        case kFoliage:
        case kBark: return SurfaceClass::vegetation;
        case kCarPaint:
        case kMattress:
        case kCardboard:
        case kMetalPole:
        case kPersonClothes: return SurfaceClass::vehicle;
        default: return SurfaceClass::other;
    }
}

}  // namespace quasiloc::sim
