#pragma once
// [BuildDatabase] as quasiloc-build-db reads it: the library's keys (reloc/database_builder.h) and the files.
#include <quasiloc/reloc/database_builder.h>
#include <string>

namespace quasiloc::app
{
struct BuildRunOptions : public reloc::DatabaseBuildOptions
{
    std::string map_file, calibration_ini, output = "out/db/database.qdb";
    void declare(core::OptionTable& t) override
    {
        DatabaseBuildOptions::declare(t);
        t.add("map_file", map_file, "the LiDAR map");
        t.add("calibration_ini", calibration_ini, "StereoRig keys, prefix camera_: the views use the left camera");
        t.add("output", output, "the database file");
    }
};

}  // namespace quasiloc::app
