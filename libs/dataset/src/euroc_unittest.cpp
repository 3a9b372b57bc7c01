#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <quasiloc/core/pose.h>
#include <quasiloc/dataset/euroc.h>
#include <quasiloc/dataset/frame_source.h>
#include <quasiloc/dataset/timestamps.h>
#include <sstream>

#include "test_helpers.h"

namespace fs = std::filesystem;
using namespace quasiloc;
using namespace quasiloc::dataset;
using quasiloc::dataset::test::microEurocFolder;
using quasiloc::dataset::test::TempDir;

namespace
{
/** Rows of a csv as strings (header skipped), read independently of the library. */
std::vector<std::vector<std::string>> csvRows(const std::string& path)
{
    std::ifstream in(path);
    std::vector<std::vector<std::string>> rows;
    std::string line;
    while (std::getline(in, line))
    {
        if (line.empty() || line[0] == '#') continue;
        if (line.back() == '\r') line.pop_back();
        std::vector<std::string> f;
        std::stringstream ss(line);
        std::string x;
        while (std::getline(ss, x, ',')) f.push_back(x);
        rows.push_back(f);
    }
    return rows;
}

/** A tiny ASL folder: the micro sequence's yaml files, its first `n` image pairs and imu rows. */
void makeTinyAsl(const std::string& root, size_t n)
{
    const std::string src = microEurocFolder() + "/mav0";
    for (const char* cam : {"cam0", "cam1"})
    {
        fs::create_directories(root + "/mav0/" + cam + "/data");
        fs::copy_file(src + "/" + cam + "/sensor.yaml", root + "/mav0/" + cam + "/sensor.yaml");
        std::ofstream csv(root + "/mav0/" + cam + "/data.csv");
        csv << "#timestamp [ns],filename\n";
        const auto rows = csvRows(src + "/" + cam + "/data.csv");
        for (size_t i = 0; i < n; ++i)
        {
            csv << rows[i][0] << "," << rows[i][1] << "\n";
            fs::copy_file(src + "/" + cam + "/data/" + rows[i][1], root + "/mav0/" + cam + "/data/" + rows[i][1]);
        }
    }
    fs::create_directories(root + "/mav0/imu0");
    std::ifstream in(src + "/imu0/data.csv");
    std::ofstream out(root + "/mav0/imu0/data.csv");
    std::string line;
    for (size_t i = 0; i < 40 && std::getline(in, line); ++i) out << line << "\n";
}
}  // namespace

TEST(Euroc, ReadsMicroSequenceIndex)
{
    const EurocSequence seq = readEurocSequence(microEurocFolder());
    const auto cam0 = csvRows(microEurocFolder() + "/mav0/cam0/data.csv");
    const auto cam1 = csvRows(microEurocFolder() + "/mav0/cam1/data.csv");
    const auto imu = csvRows(microEurocFolder() + "/mav0/imu0/data.csv");
    EXPECT_EQ(seq.cam0_rows, cam0.size());
    EXPECT_EQ(seq.cam1_rows, cam1.size());
    // Every cam0 row of the micro folder has an image and a cam1 partner; cam1 has extra rows without images.
    ASSERT_EQ(seq.pairs.size(), cam0.size());
    EXPECT_EQ(seq.numSkippedRows(), cam1.size() - cam0.size());
    for (size_t i = 0; i < seq.pairs.size(); ++i)
    {
        EXPECT_EQ(std::to_string(seq.pairs[i].t_ns), cam0[i][0]);
        EXPECT_TRUE(fs::is_regular_file(seq.pairs[i].left_png));
        EXPECT_NE(seq.pairs[i].right_png.find("/cam1/data/" + cam0[i][1]), std::string::npos);
    }
    ASSERT_EQ(seq.imu.size(), imu.size());
    for (size_t i : {size_t(0), size_t(1234), imu.size() - 1})
    {
        EXPECT_EQ(std::to_string(seq.imu_t_ns[i]), imu[i][0]);
        // EuRoC columns: w_x w_y w_z a_x a_y a_z.
        EXPECT_EQ(seq.imu[i].gyro.x(), std::stod(imu[i][1]));
        EXPECT_EQ(seq.imu[i].gyro.z(), std::stod(imu[i][3]));
        EXPECT_EQ(seq.imu[i].acc.x(), std::stod(imu[i][4]));
        EXPECT_EQ(seq.imu[i].acc.z(), std::stod(imu[i][6]));
        EXPECT_NEAR(seq.imu[i].t, std::stod(imu[i][0]) * 1e-9, 1e-6);
    }
}

TEST(Euroc, RigEqualsSensorYaml)
{
    const EurocSequence seq = readEurocSequence(microEurocFolder() + "/mav0");  // mav0/ itself works too
    // Values of cam0/sensor.yaml and cam1/sensor.yaml.
    EXPECT_EQ(seq.rig.left.width, 752);
    EXPECT_EQ(seq.rig.left.height, 480);
    EXPECT_DOUBLE_EQ(seq.rig.left.fx, 458.654);
    EXPECT_DOUBLE_EQ(seq.rig.left.cy, 248.375);
    EXPECT_DOUBLE_EQ(seq.rig.left.dist[0], -0.28340811);
    EXPECT_DOUBLE_EQ(seq.rig.right.fx, 457.587);
    EXPECT_DOUBLE_EQ(seq.rig.right.dist[3], -3.55590700e-05);
    EXPECT_NEAR(seq.rig.T_body_left.x(), -0.0216401454975, 1e-12);
    EXPECT_NEAR(seq.rig.baseline(), 0.110, 0.001);  // EuRoC's 11 cm stereo baseline
}

TEST(Euroc, OpenEurocReportsSkippedRowsAndSlicesImu)
{
    auto src = openEuroc(microEurocFolder());
    const auto warnings = src->warnings();
    // The micro folder's only defect: cam1 rows (after the last cam0 row) whose image file is missing.
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("cam1/data.csv rows whose image file is missing"), std::string::npos) << warnings[0];
    const auto cam1 = csvRows(microEurocFolder() + "/mav0/cam1/data.csv");
    EXPECT_NE(warnings[0].find(cam1.back()[0]), std::string::npos) << warnings[0];

    const EurocSequence seq = readEurocSequence(microEurocFolder());
    StereoFrame frame;
    size_t n = 0, imu_total = 0;
    double prev_t = -1;
    while (src->next(frame))
    {
        EXPECT_EQ(frame.index, n);
        // Double seconds at ~1.4e9 s resolve ~0.24 us, so the ns timestamps are kept to within 1 us.
        EXPECT_LE(std::abs(secondsToNs(frame.timestamp) - seq.pairs[n].t_ns), 1000);
        for (const auto& s : frame.imu)
        {
            EXPECT_GT(s.t, prev_t);
            EXPECT_LE(s.t, frame.timestamp);
        }
        if (n < 2)
        {
            const cv::Mat orig = cv::imread(seq.pairs[n].right_png, cv::IMREAD_UNCHANGED);
            EXPECT_EQ(cv::norm(frame.right, orig, cv::NORM_INF), 0.0);
        }
        imu_total += frame.imu.size();
        prev_t = frame.timestamp;
        ++n;
    }
    EXPECT_EQ(n, seq.pairs.size());
    const size_t imu_up_to_last =
        std::upper_bound(seq.imu_t_ns.begin(), seq.imu_t_ns.end(), seq.pairs.back().t_ns) - seq.imu_t_ns.begin();
    EXPECT_EQ(imu_total, imu_up_to_last);
}

TEST(Euroc, BadInputNamesTheFile)
{
    test::expectInputErrorMentioning([] { readEurocSequence("/nonexistent/asl"); }, "/nonexistent/asl");
    TempDir dir;
    makeTinyAsl(dir.path(), 3);
    EXPECT_EQ(readEurocSequence(dir.path()).pairs.size(), 3u);

    fs::remove(dir / "mav0/imu0/data.csv");
    test::expectInputErrorMentioning([&] { readEurocSequence(dir.path()); }, "imu0/data.csv");

    std::ofstream(dir / "mav0/imu0/data.csv") << "1403715273262142976,0.1,0.2,0.3,9.8,0.1\n";  // 6 columns
    test::expectInputErrorMentioning([&] { readEurocSequence(dir.path()); }, "imu0/data.csv:1");

    fs::remove(dir / "mav0/cam1/data.csv");
    test::expectInputErrorMentioning([&] { readEurocSequence(dir.path()); }, "cam1/data.csv");
}

TEST(Euroc, WrongImageSizeNamesTheImage)
{
    TempDir dir;
    makeTinyAsl(dir.path(), 2);
    const EurocSequence seq = readEurocSequence(dir.path());
    cv::imwrite(seq.pairs[1].left_png, cv::Mat(240, 376, CV_8UC1, cv::Scalar(7)));
    auto src = openEuroc(dir.path());
    StereoFrame frame;
    EXPECT_TRUE(src->next(frame));
    test::expectInputErrorMentioning([&] { src->next(frame); }, seq.pairs[1].left_png);
}
