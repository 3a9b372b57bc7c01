#pragma once
// [Localize]: quasiloc-localize's own section (the files, the modes, what is queried).
#include <quasiloc/core/declared_options.h>
#include <quasiloc/reloc/localizer.h>
#include <string>
#include <vector>

#include "stereo_queries.h"

namespace quasiloc::app
{
/** What is localized: the camera's left image, or the quasi-image rendered at the ground-truth pose. */
enum class QueryImage
{
    Camera,
    Quasi
};

/** One way of localizing a query: the database in a budget (fast, full), or the stereo pair against the map. */
struct QueryMode
{
    std::string name;
    bool stereo = false;
    bool structure = false;  ///< the image against the map's views by structure (reloc/structure_localizer.h)
    reloc::LocalizationMode budget = reloc::LocalizationMode::Fast;  ///< database modes
};

struct LocalizeRunOptions : public core::DeclaredOptions
{
    std::string database, input_rawlog, calibration_ini, groundtruth, map_file, output_dir = "out/localize";
    std::vector<std::string> modes{"fast", "full"};
    QueryImage query_image = QueryImage::Camera;
    int every_n = 10, max_queries = 0;
    /** Stereo queries: where up is. The IMU when the recording has one; level for a single pair without it. */
    QueryGravity gravity = QueryGravity::Imu;
    double gravity_window_s = 0.2;
    /** Stereo queries: the clouds of the last frames joined by the camera's own motion (1: the queried pair alone).
     *  Measured spans: docs/place_retrieval.md, "Multi-frame stereo queries". */
    StereoSpanSettings span;

    void declare(core::OptionTable& t) override;
    /** The modes; InputError naming `name` and the key for no or an unknown mode, a database mode without database,
     *  a stereo mode without map_file or with query_image = quasi, or a quasi query without map and ground truth. */
    std::vector<QueryMode> checkedModes(const std::string& name) const;
};

/** Whether any of `modes` localizes against the database (and so needs it). */
bool needsDatabase(const std::vector<QueryMode>& modes);
/** Whether any of `modes` is a stereo query. */
bool hasStereo(const std::vector<QueryMode>& modes);
/** Whether any of `modes` is a structure query. */
bool hasStructure(const std::vector<QueryMode>& modes);

}  // namespace quasiloc::app
