#pragma once
// [Localize]: quasiloc-localize's own section (the files, the budgets, what is queried).
#include <quasiloc/core/declared_options.h>
#include <quasiloc/reloc/localizer.h>
#include <string>
#include <vector>

namespace quasiloc::app
{
/** What is localized: the camera's left image, or the quasi-image rendered at the ground-truth pose. */
enum class QueryImage
{
    Camera,
    Quasi
};

struct LocalizeRunOptions : public core::DeclaredOptions
{
    std::string database, input_rawlog, calibration_ini, groundtruth, map_file, output_dir = "out/localize";
    std::vector<std::string> modes{"fast", "full"};
    QueryImage query_image = QueryImage::Camera;
    int every_n = 10, max_queries = 0;

    void declare(core::OptionTable& t) override;
    /** The budgets of `modes`; InputError naming `name` for a quasi query without map and ground truth, or no
     *  or an unknown mode. */
    std::vector<reloc::LocalizationMode> checkedModes(const std::string& name) const;
};

}  // namespace quasiloc::app
