// Fuzz target: program INIs through our strict option loaders: loadConfig's text, then loadOptionsChecked (unknown
// keys, strict numbers, ranges, enums, cross-key checks) for the programs' sections (docs/options.md) whose option
// declarations the fuzz build compiles: map-import, euroc2rawlog, bag2rawlog, rawlog2bag, sim-rawlog, quasiloc-eval
// (loadEvalConfig), most of quasiloc-track's and quasiloc-localize's. Not loaded here (their declarations live
// beside the pipelines, outside the fuzz build): [LargeWorld], [RawlogQuasi], [BuildDatabase], [ViewSampling],
// [LineMatching], [Association], [Vocabulary], [Localize], [Kidnap], [MapRefinement], [DirectAlignment],
// [Estimator], [Reweighting], [Lines], [Stereo]; they use the same declared-options machinery.
#include <mrpt/config/CConfigFileMemory.h>

#include <quasiloc/core/program_options.h>
#include <quasiloc/dataset/bag_options.h>
#include <quasiloc/dataset/euroc_conversion.h>
#include <quasiloc/eval/eval_config.h>
#include <quasiloc/frontend/features.h>
#include <quasiloc/frontend/point_matcher.h>
#include <quasiloc/quasi/quasi_options.h>
#include <quasiloc/reloc/geometric_localizer.h>
#include <quasiloc/reloc/localizer.h>
#include <quasiloc/sim/imu_synthesizer.h>
#include <quasiloc/sim/lidar_sampler.h>
#include <quasiloc/sim/simulation.h>
#include <quasiloc/sim/stereo_renderer.h>
#include <quasiloc/sim/world_builder.h>
#include <quasiloc/tracking/tracking_options.h>

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
        load<frontend::PointMatchingOptions>(cfg, "PointMatching");
        load<quasi::QuasiOptions>(cfg, "QuasiImage");
        load<reloc::LocalizerOptions>(cfg, "Localization");
        load<reloc::GeometricLocalizationOptions>(cfg, "GeometricLocalization");
        load<tracking::TrackingRunOptions>(cfg, "Tracking");
        load<tracking::InitializationOptions>(cfg, "Initialization");
        load<tracking::MapFactorOptions>(cfg, "MapFactors");
        load<tracking::RelocalizationOptions>(cfg, "Relocalization");
        load<sim::SimulationOptions>(cfg, "Simulation");
        load<sim::WorldOptions>(cfg, "World");
        load<sim::AppearanceOptions>(cfg, "Appearance");
        load<sim::LidarOptions>(cfg, "Lidar");
        load<sim::ImuNoiseOptions>(cfg, "IMU");
        fuzz::expectCleanError([&] { (void)eval::loadEvalConfig(cfg, "fuzz.ini"); });
    });
    return 0;
}
