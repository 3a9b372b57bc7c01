// Fuzz target: program INIs through our strict option loaders: loadConfig's text, then loadOptionsChecked (unknown
// keys, strict numbers, ranges, enums) for the sections whose options live in the reader libraries of the fuzz
// build: [MapImport], [Euroc2Rawlog], [Bag2Rawlog], [Rawlog2Bag], [Features] and quasiloc-eval's [Eval] +
// [Eval.<sequence>] (loadEvalConfig). The other sections use the same declared-options machinery.
#include <mrpt/config/CConfigFileMemory.h>

#include <quasiloc/core/program_options.h>
#include <quasiloc/dataset/bag_options.h>
#include <quasiloc/dataset/euroc_conversion.h>
#include <quasiloc/eval/eval_config.h>
#include <quasiloc/frontend/features.h>

#include "fuzz_common.h"
#include "map_import_app.h"

namespace
{
template <class Options>
void load(const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    quasiloc::fuzz::expectCleanError([&] {
        Options o;
        quasiloc::core::loadOptionsChecked(o, cfg, section, "fuzz.ini");
    });
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    using namespace quasiloc;
    core::CommandLine cmd;
    cmd.config_path = fuzz::writeInput(data, size, "program.ini");
    fuzz::expectCleanError([&] {
        const mrpt::config::CConfigFileMemory cfg = core::loadConfig(cmd);
        load<map_import::MapImportOptions>(cfg, "MapImport");
        load<dataset::Euroc2RawlogOptions>(cfg, "Euroc2Rawlog");
        load<dataset::Bag2RawlogOptions>(cfg, "Bag2Rawlog");
        load<dataset::Rawlog2BagOptions>(cfg, "Rawlog2Bag");
        load<frontend::FeatureOptions>(cfg, "Features");
        fuzz::expectCleanError([&] { (void)eval::loadEvalConfig(cfg, "fuzz.ini"); });
    });
    return 0;
}
