#include <gtest/gtest.h>
#include <mrpt/config/CLoadableOptions.h>

#include <filesystem>
#include <fstream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/core/staged_output.h>

using namespace quasiloc::core;
namespace fs = std::filesystem;

namespace
{
struct DemoOptions : public mrpt::config::CLoadableOptions
{
    double voxel_size_m = 0.05;
    std::string output = "out.map";
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override
    {
        voxel_size_m = c.read_double(s, "voxel_size_m", voxel_size_m);
        output = c.read_string(s, "output", output);
    }
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override
    {
        c.write(s, "voxel_size_m", voxel_size_m);
        c.write(s, "output", output);
    }
};

CommandLine parse(std::vector<std::string> args)
{
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    return parseCommandLine(static_cast<int>(argv.size()), argv.data());
}

std::string tempDir(const std::string& name)
{
    const fs::path d = fs::temp_directory_path() / ("quasiloc_" + name);
    fs::remove_all(d);
    fs::create_directories(d);
    return d.string();
}
}  // namespace

TEST(ProgramOptions, ParsesConfigAndOverrides)
{
    const auto cmd = parse({"prog", "a.ini", "--set", "Map.voxel_size_m=0.1", "--print-timing", "--flag"});
    EXPECT_EQ(cmd.config_path, "a.ini");
    ASSERT_EQ(cmd.overrides.size(), 1u);
    EXPECT_EQ(cmd.overrides[0].first, "Map.voxel_size_m");
    EXPECT_EQ(cmd.overrides[0].second, "0.1");
    EXPECT_TRUE(cmd.print_timing);
    ASSERT_EQ(cmd.flags.size(), 1u);
}

TEST(ProgramOptions, MalformedArgumentsAreErrors)
{
    EXPECT_THROW(parse({"prog"}), InputError);
    EXPECT_THROW(parse({"prog", "a.ini", "--set"}), InputError);
    EXPECT_THROW(parse({"prog", "a.ini", "--set", "novalue"}), InputError);
    EXPECT_THROW(parse({"prog", "a.ini", "--set", ".k=v"}), InputError);
    EXPECT_THROW(parse({"prog", "a.ini", "--set", "Section.=v"}), InputError);
}

TEST(ProgramOptions, OverridesWinAndUnknownKeysAreRejected)
{
    const std::string dir = tempDir("opts");
    const std::string ini = dir + "/a.ini";
    {
        std::ofstream f(ini);
        f << "[Map]\nvoxel_size_m = 0.2\n";
    }
    auto cmd = parse({"prog", ini, "--set", "Map.output=x.map"});
    const auto cfg = loadConfig(cmd);
    DemoOptions o;
    loadOptionsChecked(o, cfg, "Map", ini);
    EXPECT_DOUBLE_EQ(o.voxel_size_m, 0.2);
    EXPECT_EQ(o.output, "x.map");

    cmd = parse({"prog", ini, "--set", "Map.voxel_sise_m=0.3"});
    try
    {
        loadOptionsChecked(o, loadConfig(cmd), "Map", ini);
        FAIL() << "expected InputError";
    }
    catch (const InputError& e)
    {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("voxel_sise_m"), std::string::npos) << msg;
        EXPECT_NE(msg.find("voxel_size_m"), std::string::npos) << "known keys listed: " << msg;
    }
    EXPECT_THROW(loadConfig(parse({"prog", dir + "/missing.ini"})), InputError);
}

TEST(ProgramOptions, EffectiveConfigIsWrittenAndReadable)
{
    const std::string dir = tempDir("effcfg");
    DemoOptions o;
    o.voxel_size_m = 0.25;
    writeEffectiveConfig(dir + "/effective.ini", {{"Map", &o}}, "test");
    CommandLine cmd;
    cmd.config_path = dir + "/effective.ini";
    DemoOptions back;
    loadOptionsChecked(back, loadConfig(cmd), "Map", cmd.config_path);
    EXPECT_DOUBLE_EQ(back.voxel_size_m, 0.25);
}

TEST(StagedOutputs, NothingAppearsWithoutCommit)
{
    const std::string dir = tempDir("staged");
    {
        StagedOutputs out;
        const std::string tmp = out.addFile(dir + "/result.txt");
        std::ofstream(tmp) << "half";
        const std::string tmpdir = out.addFolder(dir + "/images");
        std::ofstream(tmpdir + "/a.png") << "x";
        // destroyed without commit: e.g. an exception was thrown
    }
    EXPECT_TRUE(fs::is_empty(dir)) << "temporaries must be removed";
    {
        StagedOutputs out;
        std::ofstream(out.addFile(dir + "/result.txt")) << "full";
        out.commit();
    }
    std::ifstream in(dir + "/result.txt");
    std::string s;
    in >> s;
    EXPECT_EQ(s, "full");
}

TEST(StagedOutputs, CommitReplacesAnExistingOutput)
{
    const std::string dir = tempDir("staged2");
    writeTextFileAtomically(dir + "/a.txt", "one");
    writeTextFileAtomically(dir + "/a.txt", "two");
    std::ifstream in(dir + "/a.txt");
    std::string s;
    in >> s;
    EXPECT_EQ(s, "two");
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(ProgramOptions, AnOptionalConfigIsTheFirstPlainArgumentAndNothingElseIsAccepted)
{
    CommandLine cmd;
    EXPECT_TRUE(withOptionalConfig(cmd).config_path.empty());
    cmd.flags = {"bench.ini"};
    const CommandLine with = withOptionalConfig(cmd);
    EXPECT_EQ(with.config_path, "bench.ini");
    EXPECT_TRUE(with.flags.empty());
    cmd.flags = {"bench.ini", "extra"};
    EXPECT_THROW(withOptionalConfig(cmd), InputError);
}
