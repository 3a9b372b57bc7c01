#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/trajectory_io.h>

using namespace quasiloc::core;

TEST(Pose, IsometryAndQuaternionRoundTrip)
{
    const mrpt::poses::CPose3D T(1.0, -2.0, 0.5, 0.3, -0.2, 1.1);
    const mrpt::poses::CPose3D back = fromIsometry(toIsometry(T));
    EXPECT_LT(translationDistance(T, back), 1e-12);
    EXPECT_LT(rotationDistanceRad(T, back), 1e-12);
    const auto q = quaternionOf(T);
    EXPECT_GE(q.w(), 0);
    const auto T2 = fromTranslationQuaternion({T.x(), T.y(), T.z()}, q);
    EXPECT_LT(rotationDistanceRad(T, T2), 1e-12);
}

TEST(Pose, MatrixRowMajorRejectsNonRotations)
{
    std::vector<double> good = {0, -1, 0, 1, 1, 0, 0, 2, 0, 0, 1, 3, 0, 0, 0, 1};
    const auto T = fromMatrixRowMajor(good, "test");
    EXPECT_DOUBLE_EQ(T.y(), 2.0);
    std::vector<double> scaled = good;
    scaled[0] = 0.5;
    EXPECT_THROW(fromMatrixRowMajor(scaled, "test"), InputError);
    std::vector<double> nan = good;
    nan[3] = std::nan("");
    EXPECT_THROW(fromMatrixRowMajor(nan, "test"), InputError);
    EXPECT_THROW(fromMatrixRowMajor({1, 2, 3}, "test"), InputError);
}

TEST(Pose, ComposeFollowsFrameNames)
{
    // T_a_c = T_a_b * T_b_c, and a point in c maps to a through it.
    const mrpt::poses::CPose3D T_a_b(1, 0, 0, M_PI / 2, 0, 0), T_b_c(0, 2, 0, 0, 0, 0);
    const auto T_a_c = T_a_b + T_b_c;
    const auto p_a = T_a_c.composePoint(mrpt::math::TPoint3D(0, 0, 0));
    EXPECT_NEAR(p_a.x, 1 - 2, 1e-12);  // (0,2,0) rotated by +90 deg about z is (-2,0,0)
    EXPECT_NEAR(p_a.y, 0, 1e-12);
}

TEST(TrajectoryIo, TumRoundTripAndInterpolation)
{
    Trajectory tr;
    tr.header = "T_world_cam0";
    tr.poses.push_back({10.0, mrpt::poses::CPose3D(0, 0, 0, 0, 0, 0)});
    tr.poses.push_back({11.0, mrpt::poses::CPose3D(2, 0, 0, 0.4, 0, 0)});
    const std::string path = (std::filesystem::temp_directory_path() / "quasiloc_tum_test.tum").string();
    writeTum(path, tr);
    const Trajectory back = readTum(path);
    std::filesystem::remove(path);
    ASSERT_EQ(back.poses.size(), 2u);
    EXPECT_EQ(back.header, " T_world_cam0");
    EXPECT_LT(translationDistance(back.poses[1].pose, tr.poses[1].pose), 1e-6);
    EXPECT_LT(rotationDistanceRad(back.poses[1].pose, tr.poses[1].pose), 1e-8);
    mrpt::poses::CPose3D mid;
    ASSERT_TRUE(interpolatePose(back, 10.5, mid));
    EXPECT_NEAR(mid.x(), 1.0, 1e-6);
    EXPECT_NEAR(mid.yaw(), 0.2, 1e-6);
    EXPECT_FALSE(interpolatePose(back, 12.0, mid));
    EXPECT_TRUE(interpolatePose(back, 11.05, mid, 0.1));
}

TEST(TrajectoryIo, MalformedLinesNameFileAndLine)
{
    const std::string path = (std::filesystem::temp_directory_path() / "quasiloc_bad.tum").string();
    {
        std::ofstream f(path);
        f << "# comment\n1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 1\n";
    }
    try
    {
        readTum(path);
        FAIL() << "expected InputError";
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find(path + ":3"), std::string::npos) << e.what();
    }
    {
        std::ofstream f(path);
        f << "1.0 0 0 0 0 0 0 5\n";
    }
    EXPECT_THROW(readTum(path), InputError);
    std::filesystem::remove(path);
    EXPECT_THROW(readTum("/nonexistent/x.tum"), InputError);
}

TEST(TrajectoryIo, ReadsTheEurocGroundTruth)
{
    const Trajectory t = readTum(std::string(QUASILOC_SHARED_DIR) + "/data/euroc/groundtruth/cam0/V1_01_easy.txt");
    EXPECT_EQ(t.poses.size(), 2912u);
    EXPECT_NEAR(t.poses.front().pose.x(), 0.866255498, 1e-6);
}
