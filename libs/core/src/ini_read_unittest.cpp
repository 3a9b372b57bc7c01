#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <quasiloc/core/error.h>
#include <quasiloc/core/ini_read.h>

using namespace quasiloc::core;

TEST(IniRead, ValuesDefaultsAndTypos)
{
    mrpt::config::CConfigFileMemory cfg("[s]\nd = 0.25\ni = 7\nb = Yes\nv = [1 2, 3.5]\nbad = 0.2x\nf = 2.5\n");
    EXPECT_DOUBLE_EQ(readIniDouble(cfg, "s", "d", 1.0), 0.25);
    EXPECT_DOUBLE_EQ(readIniDouble(cfg, "s", "absent", 1.0), 1.0);
    EXPECT_EQ(readIniInt(cfg, "s", "i", 0), 7);
    EXPECT_TRUE(readIniBool(cfg, "s", "b", false));
    EXPECT_EQ(readIniVector(cfg, "s", "v", {}), (std::vector<double>{1, 2, 3.5}));
    try
    {
        readIniDouble(cfg, "s", "bad", 0);
        FAIL() << "expected InputError";
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("[s] bad"), std::string::npos) << e.what();
    }
    EXPECT_THROW(readIniInt(cfg, "s", "f", 0), InputError);
    EXPECT_THROW(readIniBool(cfg, "s", "d", false), InputError);
}
