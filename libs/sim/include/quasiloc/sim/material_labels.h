#pragma once
// The material of every point of a simulated LiDAR map, beside the map (sim-rawlog writes it with
// [Simulation] write_map_materials): lidar_map_materials.bin, "QLMAT1\n", the point count as a little-endian
// uint64, then one little-endian uint16 MaterialId per point in the map's order. Ground-truth surface labels for
// statistics (surface_class.h), not read by the localizer.
#include <cstdint>
#include <string>
#include <vector>

namespace quasiloc::sim
{
/** File name of the labels inside a simulated sequence's folder. */
constexpr const char* kMaterialLabelsFile = "lidar_map_materials.bin";

/** Writes the labels (atomic: a temporary file renamed). */
void saveMaterialLabels(const std::string& path, const std::vector<uint16_t>& materials);

/** Reads the labels; InputError naming `path` when it is missing, not such a file, cut short, or holds a count other
 *  than expected_points. */
std::vector<uint16_t> loadMaterialLabels(const std::string& path, size_t expected_points);

}  // namespace quasiloc::sim
