#include <fstream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/sim/material_labels.h>

namespace quasiloc::sim
{
namespace
{
constexpr char kMagic[] = "QLMAT1\n";
constexpr size_t kMagicSize = sizeof(kMagic) - 1;
}  // namespace

void saveMaterialLabels(const std::string& path, const std::vector<uint16_t>& materials)
{
    std::string bytes(kMagic, kMagicSize);
    const uint64_t n = materials.size();
    for (int b = 0; b < 8; ++b) bytes.push_back(static_cast<char>((n >> (8 * b)) & 0xFF));
    bytes.reserve(bytes.size() + 2 * materials.size());
    for (uint16_t m : materials)
    {
        bytes.push_back(static_cast<char>(m & 0xFF));
        bytes.push_back(static_cast<char>(m >> 8));
    }
    core::writeTextFileAtomically(path, bytes);
}

std::vector<uint16_t> loadMaterialLabels(const std::string& path, size_t expected_points)
{
    std::ifstream f(path, std::ios::binary);
    core::require(f.good(), path, "cannot open the material labels");
    char head[kMagicSize + 8];
    f.read(head, sizeof head);
    core::require(f.gcount() == static_cast<std::streamsize>(sizeof head) &&
                      std::string(head, kMagicSize) == std::string(kMagic, kMagicSize),
                  path, "not a material label file (QLMAT1)");
    uint64_t n = 0;
    for (int b = 0; b < 8; ++b) n |= uint64_t(static_cast<unsigned char>(head[kMagicSize + b])) << (8 * b);
    core::require(n == expected_points, path,
                  "holds " + std::to_string(n) + " labels for a map of " + std::to_string(expected_points) + " points");
    std::vector<unsigned char> raw(2 * n);
    f.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(raw.size()));
    core::require(static_cast<uint64_t>(f.gcount()) == raw.size(), path, "cut short");
    std::vector<uint16_t> out(n);
    for (size_t i = 0; i < n; ++i) out[i] = static_cast<uint16_t>(raw[2 * i] | (raw[2 * i + 1] << 8));
    return out;
}

}  // namespace quasiloc::sim
