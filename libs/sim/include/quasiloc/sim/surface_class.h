#pragma once
// Surface classes shared by the simulator's materials and the cross-modal statistics (tests/bench_crossmodal):
// the classes of a street scene (road, road marking, facade, vegetation, vehicle, other) and, for the indoor worlds,
// the material that stands in for each:
//   road       floors (carpet, and the concrete floor of the office corridor: concrete is counted as facade, the
//              material of most of its surfaces)
//   marking    prints on flat surfaces: posters and calibration boards (the indoor counterpart of paint on a road)
//   facade     walls and ceiling: plaster, wood panels, concrete, curtains, ceiling panels
//   vegetation none indoors
//   vehicle    compact movable objects: cardboard boxes, mattresses, poles, people
#include <cstdint>
#include <quasiloc/sim/materials.h>

namespace quasiloc::sim
{
enum class SurfaceClass : uint8_t
{
    road = 0,
    marking,
    facade,
    vegetation,
    vehicle,
    other,
    count
};

constexpr int kNumSurfaceClasses = static_cast<int>(SurfaceClass::count);

/** "road", "marking", "facade", "vegetation", "vehicle", "other". */
const char* toString(SurfaceClass c);

/** The class a material stands for (see above); other for an id outside MaterialId. */
SurfaceClass surfaceClassOf(uint16_t material);

}  // namespace quasiloc::sim
