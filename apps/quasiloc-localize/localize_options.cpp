#include "localize_options.h"

#include <quasiloc/core/error.h>

namespace quasiloc::app
{
void LocalizeRunOptions::declare(core::OptionTable& t)
{
    t.add("database", database, "the database (quasiloc-build-db)");
    t.add("input_rawlog", input_rawlog, "the stereo rawlog whose left images are queried");
    t.add("calibration_ini", calibration_ini, "optional: overrides the rawlog's calibration");
    t.add("groundtruth", groundtruth, "optional TUM of T_world_cam0, for the error table");
    t.add("map_file", map_file, "the LiDAR map (query_image = quasi)");
    t.add("output_dir", output_dir, "where the outputs go");
    t.add("modes", modes, "fast, full or both");
    t.addEnum("query_image", query_image, {{"camera", QueryImage::Camera}, {"quasi", QueryImage::Quasi}},
              "the camera's left image, or the quasi-image rendered at the ground-truth pose");
    t.add("every_n", every_n, "", core::Range::atLeast(1), "query every N-th frame");
    t.add("max_queries", max_queries, "", core::Range::atLeast(0), "queries at most (0: all)");
}

std::vector<reloc::LocalizationMode> LocalizeRunOptions::checkedModes(const std::string& name) const
{
    const std::string key = name + ": [Localize] ";
    core::require(query_image == QueryImage::Camera || (!map_file.empty() && !groundtruth.empty()), key + "query_image",
                  "quasi needs map_file and groundtruth (the query is rendered at the ground-truth pose)");
    std::vector<reloc::LocalizationMode> out;
    for (const auto& m : modes) out.push_back(reloc::localizationModeFromString(m, key + "modes"));
    core::require(!out.empty(), key + "modes", "needs fast, full or both");
    return out;
}

}  // namespace quasiloc::app
