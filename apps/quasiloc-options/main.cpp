// quasiloc-options: the options reference, docs/options.md, generated from the options' declarations
// (core/declared_options.h): every INI section of every program, each key with its type, unit, range, default and
// one line of documentation.
//
//     quasiloc-options                      prints the reference (Markdown)
//     quasiloc-options --check <file.md>    exits 1 when <file.md> is not what would be printed (ctest runs it on
//                                           docs/options.md: regenerate with build/bin/quasiloc-options >
//                                           docs/options.md)
#include <mrpt/config/CConfigFileMemory.h>

#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/dataset/bag_options.h>
#include <quasiloc/dataset/euroc_conversion.h>
#include <quasiloc/eval/eval_config.h>
#include <quasiloc/map/map_build.h>
#include <quasiloc/quasi/quasi_options.h>
#include <quasiloc/quasi/rawlog_quasi.h>
#include <quasiloc/reloc/database_builder.h>
#include <quasiloc/reloc/localizer.h>
#include <quasiloc/reloc/structure_localizer.h>
#include <quasiloc/sim/imu_synthesizer.h>
#include <quasiloc/sim/large_world.h>
#include <quasiloc/sim/lidar_sampler.h>
#include <quasiloc/sim/simulation.h>
#include <quasiloc/sim/stereo_renderer.h>
#include <quasiloc/sim/world_builder.h>
#include <quasiloc/tracking/test_harness.h>
#include <quasiloc/tracking/tracking_session.h>
#include <sstream>
#include <vector>

#include "build_options.h"
#include "localize_options.h"
#include "map_import_app.h"

namespace
{
using namespace quasiloc;

/** One INI section: the options that read it (defaults as constructed) and the programs that use it, each with its
 *  own options when its defaults differ (nullptr: the first program's). */
struct Section
{
    std::string name;
    std::shared_ptr<const mrpt::config::CLoadableOptions> options;
    std::vector<std::string> programs;
    std::vector<std::shared_ptr<const mrpt::config::CLoadableOptions>> program_options;
};

template <class T>
std::shared_ptr<const mrpt::config::CLoadableOptions> make()
{
    return std::make_shared<T>();
}

/** Every program's sections, in the order a reader meets them. */
std::vector<Section> sections()
{
    std::vector<Section> out;
    std::map<std::string, size_t> index;
    auto add = [&](const std::string& program, const std::string& name,
                   std::shared_ptr<const mrpt::config::CLoadableOptions> options) {
        if (auto it = index.find(name); it != index.end())
        {
            out[it->second].programs.push_back(program);
            out[it->second].program_options.push_back(std::move(options));
            return;
        }
        index[name] = out.size();
        out.push_back({name, options, {program}, {options}});
    };
    add("sim-rawlog", "Simulation", make<sim::SimulationOptions>());
    add("sim-rawlog", "World", make<sim::WorldOptions>());
    add("sim-rawlog", "Appearance", make<sim::AppearanceOptions>());
    add("sim-rawlog", "Lidar", make<sim::LidarOptions>());
    add("sim-rawlog", "IMU", make<sim::ImuNoiseOptions>());
    add("sim-large-world", "LargeWorld", make<sim::LargeWorldOptions>());
    add("sim-large-world", "World", make<sim::WorldOptions>());
    add("sim-large-world", "Lidar", make<sim::LidarOptions>());
    add("map-import", "MapImport", make<map_import::MapImportOptions>());
    add("map-build", "MapBuild", make<map::MapBuildOptions>());
    add("euroc2rawlog", "Euroc2Rawlog", make<dataset::Euroc2RawlogOptions>());
    add("bag2rawlog", "Bag2Rawlog", make<dataset::Bag2RawlogOptions>());
    add("rawlog2bag", "Rawlog2Bag", make<dataset::Rawlog2BagOptions>());
    add("rawlog-quasi", "RawlogQuasi", make<quasi::RawlogQuasiOptions>());
    add("rawlog-quasi", "QuasiImage", make<quasi::QuasiOptions>());
    // quasiloc-track: the session's own list, so this reference cannot drift from what the program reads.
    auto session = std::make_shared<tracking::SessionOptions>();
    for (const core::OptionsSection& s : session->sections())
        add("quasiloc-track", s.section, std::shared_ptr<const mrpt::config::CLoadableOptions>(session, s.options));
    // The test harness's own sections (quasiloc-track-harness reads quasiloc-track's too; quasiloc-track refuses
    // these).
    auto harness = std::make_shared<tracking::HarnessOptions>();
    for (const core::OptionsSection& s : harness->sections())
        add("quasiloc-track-harness", s.section,
            std::shared_ptr<const mrpt::config::CLoadableOptions>(harness, s.options));
    auto build = std::make_shared<reloc::DatabaseBuildConfig>();
    add("quasiloc-build-db", "BuildDatabase", make<app::BuildRunOptions>());
    add("quasiloc-build-db", "ViewSampling",
        std::shared_ptr<const mrpt::config::CLoadableOptions>(build, &build->sampling));
    add("quasiloc-build-db", "QuasiImage", make<quasi::QuasiOptions>());
    auto frontend = std::make_shared<frontend::FrontendOptions>();
    add("quasiloc-build-db", "Features",
        std::shared_ptr<const mrpt::config::CLoadableOptions>(frontend, &frontend->features));
    for (const char* s : {"PointMatching", "Lines", "Stereo"}) add("quasiloc-build-db", s, nullptr);
    add("quasiloc-build-db", "LineMatching",
        std::shared_ptr<const mrpt::config::CLoadableOptions>(frontend, &frontend->line_matching));
    add("quasiloc-build-db", "Association",
        std::shared_ptr<const mrpt::config::CLoadableOptions>(frontend, &frontend->association));
    add("quasiloc-build-db", "Vocabulary",
        std::shared_ptr<const mrpt::config::CLoadableOptions>(build, &build->vocabulary));
    add("quasiloc-localize", "Localize", make<app::LocalizeRunOptions>());
    add("quasiloc-localize", "Localization", make<reloc::LocalizerOptions>());
    add("quasiloc-localize", "PointMatching", nullptr);
    add("quasiloc-localize", "QuasiImage", make<quasi::QuasiOptions>());
    add("quasiloc-localize", "GeometricLocalization", nullptr);
    add("quasiloc-localize", "StructureLocalization", make<reloc::StructureLocalizerOptions>());
    add("quasiloc-eval", "Eval", make<eval::EvalOptions>());
    add("quasiloc-eval", "Eval.<sequence>", make<eval::SequenceOptions>());
    return out;
}

std::string cell(std::string text)
{
    for (size_t p = 0; (p = text.find('|', p)) != std::string::npos; p += 2) text.replace(p, 1, "\\|");
    return text.empty() ? " " : text;
}

/** The keys of options that do not declare them: the names and defaults their saveToConfigFile writes. */
std::vector<core::OptionDescription> undeclared(const mrpt::config::CLoadableOptions& o)
{
    mrpt::config::CConfigFileMemory mem;
    o.saveToConfigFile(mem, "S");
    std::vector<core::OptionDescription> out;
    for (const std::string& key : core::knownKeys(o, "S"))
        out.push_back({key, "", "", "", mem.read_string("S", key, "", false), "(not declared yet)"});
    return out;
}

std::string shownDefault(const std::string& value) { return value.empty() ? "(empty)" : "`" + value + "`"; }

/** The key's default; where the programs' own options default it differently, each program's. */
std::string defaults(const Section& s, const core::OptionDescription& key)
{
    std::vector<std::pair<std::string, std::string>> per_program;  // (default, program)
    bool differ = false;
    for (size_t i = 0; i < s.programs.size(); ++i)
    {
        const auto* declared = dynamic_cast<const core::DeclaredOptions*>(s.program_options[i].get());
        if (!declared) continue;
        for (const auto& d : declared->describe())
            if (d.key == key.key)
            {
                differ = differ || d.default_value != key.default_value;
                per_program.emplace_back(d.default_value, s.programs[i]);
            }
    }
    if (!differ) return shownDefault(key.default_value);
    std::string out;
    for (const auto& [value, program] : per_program)
        out += (out.empty() ? "" : "; ") + shownDefault(value) + " (" + program + ")";
    return out;
}

std::string reference()
{
    std::ostringstream md;
    md << "# Options reference\n\n"
       << "Generated by `build/bin/quasiloc-options > docs/options.md` from each option's one declaration\n"
          "(`libs/core/include/quasiloc/core/declared_options.h`); ctest fails when this file is out of date.\n"
          "Every program reads an INI file, `--set Section.key=value` overrides a key, and an unknown key is an "
          "error.\n"
          "Ranges are checked when the file is read; checks that relate two keys are named in the error.\n";
    for (const Section& s : sections())
    {
        md << "\n## [" << s.name << "]\n\nRead by: ";
        for (size_t i = 0; i < s.programs.size(); ++i) md << (i ? ", " : "") << "`" << s.programs[i] << "`";
        md << "\n\n| key | type | unit | range | default | meaning |\n|---|---|---|---|---|---|\n";
        const auto* declared = dynamic_cast<const core::DeclaredOptions*>(s.options.get());
        const auto keys = declared ? declared->describe() : undeclared(*s.options);
        for (const auto& k : keys)
            md << "| `" << k.key << "` | " << cell(k.type) << " | " << cell(k.unit) << " | " << cell(k.range) << " | "
               << defaults(s, k) << " | " << cell(k.doc) << " |\n";
    }
    return md.str();
}
}  // namespace

int main(int argc, char** argv)
{
    try
    {
        const std::string text = reference();
        if (argc == 3 && std::string(argv[1]) == "--check")
        {
            std::ifstream in(argv[2]);
            std::stringstream current;
            current << in.rdbuf();
            if (current.str() == text) return 0;
            std::cerr << "quasiloc-options: " << argv[2]
                      << " is out of date: regenerate it with build/bin/quasiloc-options > docs/options.md\n";
            return 1;
        }
        if (argc != 1)
        {
            std::cerr << "usage: quasiloc-options [--check <options.md>]\n";
            return 2;
        }
        std::cout << text;
        return 0;
    }
    catch (const std::exception& e)
    {
        std::cerr << "quasiloc-options: error: " << e.what() << "\n";
        return 1;
    }
}
