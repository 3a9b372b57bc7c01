#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <quasiloc/core/declared_options.h>
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>

using namespace quasiloc::core;

namespace
{
enum class Budget
{
    Fast,
    Full
};

struct DemoOptions : public DeclaredOptions
{
    double max_depth_m = 6;
    int keyframe_every = 1;
    bool dense = true;
    std::string map_file;
    std::vector<double> heights_m{0.5, 1.5};
    Budget budget = Budget::Fast;
    void declare(OptionTable& t) override
    {
        t.add("max_depth_m", max_depth_m, "m", Range::above(0), "farther points are dropped");
        t.add("keyframe_every", keyframe_every, "frames", Range::atLeast(1), "a map update every N frames");
        t.add("dense", dense, "the dense stereo cloud");
        t.add("map_file", map_file, "the LiDAR map");
        t.add("heights_m", heights_m, "m", Range::atLeast(0), "view heights");
        t.addEnum("budget", budget, {{"fast", Budget::Fast}, {"full", Budget::Full}}, "the search budget");
    }
};

mrpt::config::CConfigFileMemory ini(const std::string& text)
{
    mrpt::config::CConfigFileMemory cfg;
    cfg.setContent(text);
    return cfg;
}

std::string loadError(const std::string& text)
{
    DemoOptions o;
    try
    {
        loadOptionsChecked(o, ini(text), "Demo", "demo.ini");
    }
    catch (const InputError& e)
    {
        return e.what();
    }
    return "";
}
}  // namespace

TEST(DeclaredOptions, LoadsEveryDeclaredTypeAndKeepsDefaultsOfAbsentKeys)
{
    DemoOptions o;
    loadOptionsChecked(o, ini("[Demo]\nmax_depth_m = 4.5\ndense = false\nheights_m = [1 2]\nbudget = full\n"), "Demo",
                       "demo.ini");
    EXPECT_DOUBLE_EQ(o.max_depth_m, 4.5);
    EXPECT_FALSE(o.dense);
    EXPECT_EQ(o.heights_m, (std::vector<double>{1, 2}));
    EXPECT_EQ(o.budget, Budget::Full);
    EXPECT_EQ(o.keyframe_every, 1);
    loadOptionsChecked(o, ini("[Demo]\nbudget = Fast\n"), "Demo", "demo.ini");
    EXPECT_EQ(o.budget, Budget::Fast);
}

TEST(DeclaredOptions, RejectsOutOfRangeWrongTypeUnknownEnumAndUnknownKeyNamingTheKey)
{
    EXPECT_NE(
        loadError("[Demo]\nmax_depth_m = 0\n").find("demo.ini [Demo] max_depth_m: '0' is out of range (must be > 0)"),
        std::string::npos);
    EXPECT_NE(loadError("[Demo]\nkeyframe_every = 1.5\n").find("is not an integer"), std::string::npos);
    EXPECT_NE(loadError("[Demo]\nbudget = quick\n").find("'quick' is not one of fast, full"), std::string::npos);
    EXPECT_NE(loadError("[Demo]\nheights_m = 1 -2\n").find("each value must be >= 0"), std::string::npos);
    EXPECT_NE(loadError("[Demo]\nmax_dept_m = 3\n").find("unknown key"), std::string::npos);
    EXPECT_EQ(loadError("[Demo]\nmax_depth_m = 0\n").rfind("demo.ini [Demo] max_depth_m", 0), 0u);
}

TEST(DeclaredOptions, SavedValuesLoadBackToTheSameOptions)
{
    DemoOptions a;
    a.max_depth_m = 0.05;
    a.budget = Budget::Full;
    a.heights_m = {0.25};
    mrpt::config::CConfigFileMemory mem;
    a.saveToConfigFile(mem, "Demo");
    DemoOptions b;
    loadOptionsChecked(b, ini(mem.getContent()), "Demo", "saved");  // as the effective configuration file is read
    EXPECT_EQ(b.max_depth_m, 0.05);
    EXPECT_EQ(b.budget, Budget::Full);
    EXPECT_EQ(b.heights_m, a.heights_m);
    EXPECT_EQ(knownKeys(a, "Demo").size(), 6u);
}

TEST(DeclaredOptions, DescribesEachKeyWithTypeUnitRangeDefaultAndDoc)
{
    const auto d = DemoOptions().describe();
    ASSERT_EQ(d.size(), 6u);
    EXPECT_EQ(d[0].key, "max_depth_m");
    EXPECT_EQ(d[0].unit, "m");
    EXPECT_EQ(d[0].range, "> 0");
    EXPECT_EQ(d[0].default_value, "6");
    EXPECT_EQ(d[1].range, ">= 1");
    EXPECT_EQ(d[5].range, "fast, full");
    EXPECT_EQ(d[5].default_value, "fast");
    EXPECT_EQ(Range::fromUpTo(0, 1).text(), "[0, 1)");
    EXPECT_EQ(Range::atLeast(3000).text(), ">= 3000");  // integers in full, not 3e+03
    DemoOptions round;
    round.max_depth_m = 20;
    round.keyframe_every = 200;
    EXPECT_EQ(round.describe()[0].default_value, "20");  // not 2e+01
    EXPECT_EQ(round.describe()[1].default_value, "200");
}

namespace
{
struct SeedOptions : public DeclaredOptions
{
    size_t seed = 1;
    std::string path;  // empty by default: saved without a comment
    std::vector<double> bias{0.1, 1.0 / 3};
    Eigen::Vector3d gyro{1e-17, -0.0023, 2.0 / 3};
    Budget budget = Budget::Full;
    void declare(OptionTable& t) override
    {
        t.add("seed", seed, "", Range::any(), "generator seed");
        t.add("path", path, "an optional file");
        t.add("bias", bias, "m", Range::between(-1, 1), "a bias");
        t.add("gyro", gyro, "rad/s", Range::any(), "a 3-vector");
        t.addEnum("budget", budget, {{"fast", Budget::Fast}, {"full", Budget::Full}, {"complete", Budget::Full}},
                  "the search budget (complete: an old name of full)");
    }
};
}  // namespace

TEST(DeclaredOptions, EmptyTextSeedsAbove2To53FullPrecisionVectorsAndAliasesLoadBack)
{
    SeedOptions a;
    a.seed = 18446744073709551557ull;
    mrpt::config::CConfigFileMemory mem;
    a.saveToConfigFile(mem, "S");
    SeedOptions b;
    b.path = "x";
    loadOptionsChecked(b, ini(mem.getContent()), "S", "saved");
    EXPECT_EQ(b.seed, a.seed);
    EXPECT_EQ(b.path, "");
    EXPECT_EQ(b.bias, a.bias);
    EXPECT_EQ(b.gyro, a.gyro);
    SeedOptions c;
    loadOptionsChecked(c, mem, "S", "the same object");  // not re-parsed from text
    EXPECT_EQ(c.seed, a.seed);
    EXPECT_NE(mem.getContent().find("full"), std::string::npos);  // the first name of a value is saved
    loadOptionsChecked(b, ini("[S]\nbudget = complete\n"), "S", "old.ini");
    EXPECT_EQ(b.budget, Budget::Full);
    EXPECT_THROW(loadOptionsChecked(b, ini("[S]\ngyro = [1 2]\n"), "S", "t"), InputError);
    for (const char* bad : {"-1", "1.5", "x", "18446744073709551616"})
        EXPECT_THROW(loadOptionsChecked(b, ini(std::string("[S]\nseed = ") + bad + "\n"), "S", "t"), InputError) << bad;
}

TEST(DeclaredOptions, CheckDeclaredRangesNamesTheKeyOfAValueSetInCode)
{
    SeedOptions o;
    EXPECT_NO_THROW(o.checkRanges("test [S]"));
    o.bias = {0, 2};
    try
    {
        o.checkRanges("test [S]");
        ADD_FAILURE() << "out of range accepted";
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("test [S] bias: 2 is out of range (must be [-1, 1])"), std::string::npos)
            << e.what();
    }
}

TEST(DeclaredOptions, NameListsLoadAndSaveBack)
{
    struct Names : public DeclaredOptions
    {
        std::vector<std::string> names{"a"};
        void declare(OptionTable& t) override { t.add("names", names, "the names"); }
    } o, back;
    loadOptionsChecked(o, ini("[N]\nnames = [v101, v102 x]\n"), "N", "n.ini");
    EXPECT_EQ(o.names, (std::vector<std::string>{"v101", "v102", "x"}));
    mrpt::config::CConfigFileMemory mem;
    o.saveToConfigFile(mem, "N");
    loadOptionsChecked(back, ini(mem.getContent()), "N", "saved");
    EXPECT_EQ(back.names, o.names);
    EXPECT_EQ(o.describe()[0].default_value, "[v101 v102 x]");
}

TEST(DeclaredOptions, CheckRangesTestsValuesSetInCode)
{
    DemoOptions o;
    EXPECT_NO_THROW(o.checkRanges("code", "Demo"));
    o.max_depth_m = -1;
    try
    {
        o.checkRanges("code", "Demo");
        FAIL() << "no error for max_depth_m = -1";
    }
    catch (const InputError& e)
    {
        EXPECT_EQ(std::string(e.what()), "code: [Demo] max_depth_m: -1 is out of range (must be > 0)");
    }
    o = DemoOptions();
    o.heights_m = {1, -1};
    EXPECT_THROW(o.checkRanges("code", "Demo"), InputError);
}
