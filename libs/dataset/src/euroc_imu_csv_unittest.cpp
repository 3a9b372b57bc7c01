// readEurocImuCsv / readEurocBiasCsv: the real files read exactly, every kind of bad input named by file.
#include <gtest/gtest.h>

#include <fstream>
#include <quasiloc/dataset/euroc_imu_csv.h>

#include "test_helpers.h"

using namespace quasiloc::dataset;
using quasiloc::dataset::test::expectInputErrorMentioning;
using quasiloc::dataset::test::TempDir;

namespace
{
const std::string kRealImu = test::microEurocFolder() + "/mav0/imu0/data.csv";
const std::string kBody = std::string(QUASILOC_SHARED_DIR) + "/data/euroc/groundtruth/body/V1_02_medium.csv";
const std::string kHeader = "#timestamp [ns],w_RS_S_x,w_RS_S_y,w_RS_S_z,a_RS_S_x,a_RS_S_y,a_RS_S_z\n";

std::string writeFile(const TempDir& dir, const std::string& name, const std::string& text)
{
    const std::string path = dir / name;
    std::ofstream(path) << text;
    return path;
}
}  // namespace

TEST(EurocImuCsv, ReadsTheWholeRealFileExactly)
{
    const EurocImuCsv imu = readEurocImuCsv(kRealImu);
    ASSERT_EQ(imu.samples.size(), 29120u);
    ASSERT_EQ(imu.t_ns.size(), imu.samples.size());
    EXPECT_EQ(imu.path, kRealImu);
    EXPECT_EQ(imu.t_ns.front(), 1403715273262142976);
    EXPECT_EQ(imu.samples.front().gyro.x(), -0.0020943951023931952);
    EXPECT_EQ(imu.samples.front().acc.x(), 9.0874956666666655);
    EXPECT_EQ(imu.t_ns.back(), 1403715418857143040);
    EXPECT_EQ(imu.samples.back().gyro.z(), 0.074001960284559576);
    EXPECT_EQ(imu.samples.back().acc.z(), -3.2035056666666666);
    EXPECT_NEAR(imu.samples.back().t, 1403715418.857143040, 1e-6);
    std::int64_t max_dt = 0;
    for (size_t i = 1; i < imu.t_ns.size(); ++i) max_dt = std::max(max_dt, imu.t_ns[i] - imu.t_ns[i - 1]);
    std::printf("[ real imu ] %zu samples over %.3f s, largest interval %.6f ms (gap bound %.1f ms)\n", imu.t_ns.size(),
                (imu.t_ns.back() - imu.t_ns.front()) * 1e-9, max_dt * 1e-6, kMaxImuGapPeriods * 1e3 / kEurocImuRateHz);
    EXPECT_LT(max_dt, 5.001e6);
}

TEST(EurocImuCsv, ReadsTheGroundTruthBiases)
{
    const EurocBiasCsv b = readEurocBiasCsv(kBody);
    ASSERT_EQ(b.t_ns.size(), 16702u);
    ASSERT_EQ(b.gyro_bias.size(), b.t_ns.size());
    ASSERT_EQ(b.acc_bias.size(), b.t_ns.size());
    EXPECT_EQ(b.t_ns.front(), 1403715524907143168);
    // 1403715524907143168,...,-0.002153,0.020744,0.075806,-0.013337,0.103464,0.093086
    EXPECT_EQ(b.gyro_bias.front(), Eigen::Vector3d(-0.002153, 0.020744, 0.075806));
    EXPECT_EQ(b.acc_bias.front(), Eigen::Vector3d(-0.013337, 0.103464, 0.093086));
}

TEST(EurocImuCsv, BadInputNamesTheFileAndLine)
{
    TempDir dir;
    const std::string a = "1000000000,0.1,0.2,0.3,9.8,0.1,0.2\n", b = "1005000000,0.1,0.2,0.3,9.8,0.1,0.2\n";
    EXPECT_EQ(readEurocImuCsv(writeFile(dir, "ok.csv", kHeader + a + b)).samples.size(), 2u);
    // One dropped sample (10 ms = 2 periods) passes.
    EXPECT_EQ(readEurocImuCsv(writeFile(dir, "drop.csv", kHeader + a + "1010000000,0,0,0,0,0,0\n")).samples.size(), 2u);

    expectInputErrorMentioning([&] { readEurocImuCsv(dir / "missing.csv"); }, dir / "missing.csv");
    expectInputErrorMentioning([&] { readEurocImuCsv(writeFile(dir, "empty.csv", kHeader)); }, "empty.csv");
    const auto gap = writeFile(dir, "gap.csv", kHeader + a + "1012600000,0,0,0,0,0,0\n");  // 12.6 ms > 2.5 periods
    expectInputErrorMentioning([&] { readEurocImuCsv(gap); }, "gap.csv:3: gap of 12.6");
    const auto back = writeFile(dir, "back.csv", kHeader + b + a);
    expectInputErrorMentioning([&] { readEurocImuCsv(back); }, "back.csv:3: timestamps not increasing");
    const auto dup = writeFile(dir, "dup.csv", kHeader + a + b + b);
    expectInputErrorMentioning([&] { readEurocImuCsv(dup); }, "dup.csv:4: duplicated timestamp");
    const auto cols = writeFile(dir, "cols.csv", kHeader + a + "1005000000,0.1,0.2,0.3,9.8,0.1\n");
    expectInputErrorMentioning([&] { readEurocImuCsv(cols); }, "cols.csv:3: expected 7 columns");
    const auto num = writeFile(dir, "num.csv", kHeader + a + "1005000000,0.1,0.2,abc,9.8,0.1,0.2\n");
    expectInputErrorMentioning([&] { readEurocImuCsv(num); }, "num.csv:3: 'abc' is not a finite number");
    const auto nan = writeFile(dir, "nan.csv", kHeader + a + "1005000000,0.1,0.2,nan,9.8,0.1,0.2\n");
    expectInputErrorMentioning([&] { readEurocImuCsv(nan); }, "nan.csv:3");
    const auto time = writeFile(dir, "time.csv", kHeader + "1.0e9,0.1,0.2,0.3,9.8,0.1,0.2\n");
    expectInputErrorMentioning([&] { readEurocImuCsv(time); }, "time.csv:2: timestamp '1.0e9'");
    // The gap bound follows the nominal rate: 10 ms is 4 periods at 400 Hz.
    expectInputErrorMentioning([&] { readEurocImuCsv(dir / "drop.csv", 400); }, "drop.csv:3: gap");

    expectInputErrorMentioning([&] { readEurocBiasCsv(dir / "ok.csv"); }, "ok.csv:2: expected 17 columns");
    expectInputErrorMentioning([&] { readEurocBiasCsv(dir / "no_body.csv"); }, "no_body.csv");
}
