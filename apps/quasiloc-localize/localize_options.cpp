#include "localize_options.h"

#include <quasiloc/core/error.h>

namespace quasiloc::app
{
void LocalizeRunOptions::declare(core::OptionTable& t)
{
    t.add("database", database, "the database (quasiloc-build-db); modes fast and full");
    t.add("input_rawlog", input_rawlog, "the stereo rawlog whose left images are queried");
    t.add("calibration_ini", calibration_ini, "optional: overrides the rawlog's calibration");
    t.add("groundtruth", groundtruth, "optional TUM of T_world_cam0, for the error table");
    t.add("map_file", map_file, "the LiDAR map (mode stereo, and query_image = quasi)");
    t.add("output_dir", output_dir, "where the outputs go");
    t.add("modes", modes,
          "any of fast, full (the left image against the database, in that budget), structure (the left image "
          "against the database's views rendered from map_file, by gradient-orientation structure, "
          "[StructureLocalization]) and stereo (the raw stereo pair's geometry against the map, "
          "[GeometricLocalization])");
    t.addEnum("query_image", query_image, {{"camera", QueryImage::Camera}, {"quasi", QueryImage::Quasi}},
              "the camera's left image, or the quasi-image rendered at the ground-truth pose");
    t.add("every_n", every_n, "", core::Range::atLeast(1), "query every N-th frame");
    t.add("max_queries", max_queries, "", core::Range::atLeast(0), "queries at most (0: all)");
    t.addEnum("gravity", gravity, {{"imu", QueryGravity::Imu}, {"level", QueryGravity::Level}},
              "stereo mode: up from the accelerometer (mean over gravity_window_s before the frame), or the camera "
              "taken as level (image rows and optical axis horizontal) for a pair without IMU");
    t.add("gravity_window_s", gravity_window_s, "s", core::Range::between(0.005, 5),
          "stereo mode, gravity = imu: the accelerometer span averaged for up");
    t.add("stereo_span_frames", span.frames, "frames", core::Range::between(1, 400),
          "stereo mode: the stereo clouds of this many frames up to the queried one, joined into its camera by a "
          "frame-to-frame stereo odometry (ORB, PnP, the gyroscope as a check) and localized as one query; 1: the "
          "queried pair alone. A refused odometry step ends the span there");
    t.add("stereo_span_cloud_step", span.cloud_step, "frames", core::Range::between(1, 100),
          "stereo mode, stereo_span_frames > 1: every N-th frame of the span (counted back from the queried one) "
          "gives its stereo cloud; the odometry runs on every frame");
    t.add("stereo_span_max_points", span.max_points, "points", core::Range::between(200, 100000),
          "stereo mode, stereo_span_frames > 1: the joined cloud thinned to at most this many points (after one "
          "point per query_voxel_m voxel)");
}

std::vector<QueryMode> LocalizeRunOptions::checkedModes(const std::string& name) const
{
    const std::string key = name + ": [Localize] ";
    core::require(query_image == QueryImage::Camera || (!map_file.empty() && !groundtruth.empty()), key + "query_image",
                  "quasi needs map_file and groundtruth (the query is rendered at the ground-truth pose)");
    std::vector<QueryMode> out;
    for (const auto& m : modes)
    {
        QueryMode mode{m};
        mode.stereo = m == "stereo";
        mode.structure = m == "structure";
        if (!mode.stereo && !mode.structure) mode.budget = reloc::localizationModeFromString(m, key + "modes");
        out.push_back(mode);
    }
    core::require(!out.empty(), key + "modes", "needs any of fast, full, structure, stereo");
    core::require(!needsDatabase(out) || !database.empty(), key + "database", "modes fast and full need a database");
    core::require(!hasStereo(out) || !map_file.empty(), key + "map_file", "mode stereo needs the map");
    core::require(!hasStructure(out) || !map_file.empty(), key + "map_file",
                  "mode structure needs the map (its views are rendered from it)");
    core::require(!hasStereo(out) || query_image == QueryImage::Camera, key + "query_image",
                  "mode stereo localizes the camera's stereo pair; quasi applies to the database modes only");
    return out;
}

bool needsDatabase(const std::vector<QueryMode>& modes)
{
    for (const auto& m : modes)
        if (!m.stereo) return true;
    return false;
}

bool hasStereo(const std::vector<QueryMode>& modes)
{
    for (const auto& m : modes)
        if (m.stereo) return true;
    return false;
}

bool hasStructure(const std::vector<QueryMode>& modes)
{
    for (const auto& m : modes)
        if (m.structure) return true;
    return false;
}

}  // namespace quasiloc::app
