// The checks of the place descriptor's options, apart from the descriptors: the programs' option tables (and the
// fuzz build of the INI reader) link them without the distance field.
#include <quasiloc/core/error.h>
#include <quasiloc/core/ini_read.h>
#include <quasiloc/reloc/place_descriptor.h>

namespace quasiloc::reloc
{
void PlaceDescriptorOptions::check(const std::string& input, const std::string& section) const
{
    const auto key = [&](const char* k) { return input + ": " + core::iniKeyName(section, k); };
    core::require(sectors >= 8 && sectors <= 720, key("place_sectors"), "must be in [8, 720]");
    core::require(max_range_m > 0, key("place_range_m"), "must be > 0");
    core::require(!band_offsets_m.empty(), key("place_band_offsets_m"), "needs at least one height");
    core::require(!band_centres_m.empty() && band_centres_m.size() <= 16, key("place_band_centres_m"),
                  "needs 1 to 16 bands");
    core::require(band_half_m > 0, key("place_band_half_m"), "must be > 0");
    core::require(hit_m > 0, key("place_hit_m"), "must be > 0");
    core::require(cost_truncation_m > 0, key("place_cost_truncation_m"), "must be > 0");
}

}  // namespace quasiloc::reloc
