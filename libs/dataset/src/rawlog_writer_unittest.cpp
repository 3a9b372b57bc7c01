#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/serialization/CArchive.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <quasiloc/core/pose.h>
#include <quasiloc/dataset/frame_source.h>
#include <quasiloc/dataset/rawlog_writer.h>
#include <quasiloc/dataset/timestamps.h>
#include <random>

#include "test_helpers.h"

namespace fs = std::filesystem;
using namespace quasiloc;
using namespace quasiloc::dataset;
using quasiloc::dataset::test::TempDir;

namespace
{
core::StereoRig smallRig()
{
    core::StereoRig rig;
    rig.left = core::CameraModel::pinhole(64, 48, 50.0, 51.0, 31.5, 23.5);
    rig.left.model = core::DistortionModel::RadTan;
    rig.left.dist = {-0.2, 0.05, 0.001, -0.0005, 0.0};
    rig.right = core::CameraModel::pinhole(64, 48, 52.0, 53.0, 32.5, 24.0);
    rig.T_left_right = mrpt::poses::CPose3D(0.11, 0.002, -0.001, 0.01, -0.02, 0.005);
    rig.T_body_left = mrpt::poses::CPose3D(-0.02, -0.06, 0.01, 1.58, 0.02, 0.03);
    return rig;
}

cv::Mat randomImage(int w, int h, unsigned seed)
{
    cv::Mat img(h, w, CV_8UC1);
    cv::RNG rng(seed);
    rng.fill(img, cv::RNG::UNIFORM, 0, 256);
    return img;
}

ImuSample imuSample(double t, int k)
{
    ImuSample s;
    s.t = t;
    s.acc = {0.1 * k, 9.81 - 0.01 * k, -0.3};
    s.gyro = {0.001 * k, -0.002, 0.5 + 0.001 * k};
    return s;
}
}  // namespace

TEST(RawlogWriter, DestroyedWithoutCloseLeavesNoFiles)
{
    TempDir dir;
    const core::StereoRig rig = smallRig();
    {
        RawlogWriter w(dir / "seq.rawlog", rig);
        w.writeImu(imuSample(10.0, 0));
        w.writeStereo(10.0, randomImage(64, 48, 1), randomImage(64, 48, 2));
        EXPECT_EQ(w.numStereo(), 1u);
        EXPECT_EQ(w.numImu(), 1u);
        EXPECT_FALSE(fs::exists(dir / "seq.rawlog"));  // staged: nothing at the final path yet
    }
    EXPECT_TRUE(fs::is_empty(dir.path())) << "files left behind in " << dir.path();
}

TEST(RawlogWriter, WritesObservationsMrptCanRead)
{
    TempDir dir;
    const core::StereoRig rig = smallRig();
    const std::int64_t t_ns = 1403715273262142976;
    {
        RawlogWriter w(dir / "seq.rawlog", rig);
        w.writeImuNs(t_ns - 5000000, imuSample(0, 3));
        w.writeStereoNs(t_ns, randomImage(64, 48, 1), randomImage(64, 48, 2));
        w.close();
    }
    ASSERT_TRUE(fs::is_regular_file(dir / "seq.rawlog"));
    const std::string left_png = dir / ("seq_Images/stereo_" + std::to_string(t_ns) + "_left.png");
    ASSERT_TRUE(fs::is_regular_file(left_png));

    // Read with plain MRPT calls to check the on-disk layout other MRPT tools rely on.
    mrpt::io::CFileGZInputStream in(dir / "seq.rawlog");
    auto arch = mrpt::serialization::archiveFrom(in);
    mrpt::obs::CActionCollection::Ptr act;
    mrpt::obs::CSensoryFrame::Ptr sf;
    mrpt::obs::CObservation::Ptr obs;
    size_t entry = 0;
    ASSERT_TRUE(mrpt::obs::CRawlog::getActionObservationPairOrObservation(arch, act, sf, obs, entry));
    auto imu = std::dynamic_pointer_cast<mrpt::obs::CObservationIMU>(obs);
    ASSERT_TRUE(imu);
    EXPECT_EQ(imu->sensorLabel, "imu");
    EXPECT_DOUBLE_EQ(imu->get(mrpt::obs::IMU_X_ACC), 0.3);
    EXPECT_DOUBLE_EQ(imu->get(mrpt::obs::IMU_WX), 0.003);
    EXPECT_DOUBLE_EQ(imu->get(mrpt::obs::IMU_WZ), 0.503);
    EXPECT_FALSE(imu->has(mrpt::obs::IMU_X_VEL));
    EXPECT_LE(std::abs(mrptTimeToNs(imu->timestamp) - (t_ns - 5000000)), 50);  // nearest 100 ns tick

    ASSERT_TRUE(mrpt::obs::CRawlog::getActionObservationPairOrObservation(arch, act, sf, obs, entry));
    auto stereo = std::dynamic_pointer_cast<mrpt::obs::CObservationStereoImages>(obs);
    ASSERT_TRUE(stereo);
    EXPECT_EQ(stereo->sensorLabel, "stereo");
    EXPECT_TRUE(stereo->hasImageRight);
    EXPECT_TRUE(stereo->imageLeft.isExternallyStored());
    EXPECT_EQ(stereo->imageLeft.getExternalStorageFile(), "stereo_" + std::to_string(t_ns) + "_left.png");
    // 100 ns MRPT ticks: the nearest tick to the ns timestamp.
    EXPECT_LE(std::abs(mrptTimeToNs(stereo->timestamp) - t_ns), 50);
    EXPECT_NEAR(mrpt::Clock::toDouble(stereo->timestamp), nsToSeconds(t_ns), 1e-6);
    EXPECT_DOUBLE_EQ(stereo->leftCamera.fx(), 50.0);
    EXPECT_DOUBLE_EQ(stereo->leftCamera.k1(), -0.2);
    EXPECT_DOUBLE_EQ(stereo->rightCamera.cx(), 32.5);
    EXPECT_NEAR(mrpt::poses::CPose3D(stereo->rightCameraPose).x(), 0.11, 1e-12);
    EXPECT_NEAR(mrpt::poses::CPose3D(stereo->cameraPose).yaw(), 1.58, 1e-9);
    EXPECT_FALSE(mrpt::obs::CRawlog::getActionObservationPairOrObservation(arch, act, sf, obs, entry));
}

TEST(RawlogWriter, RoundTripThroughOpenRawlog)
{
    TempDir dir;
    const core::StereoRig rig = smallRig();
    std::vector<cv::Mat> lefts, rights;
    {
        RawlogWriter::Options o;
        o.stereo_sensor_label = "cam";
        RawlogWriter w(dir / "rt.rawlog", rig, o);
        int k = 0;
        for (int f = 0; f < 3; ++f)
        {
            // IMU at 10x the frame rate, one of them stamped exactly at the frame time.
            for (int i = 0; i < 10; ++i) w.writeImu(imuSample(100.0 + f * 0.1 + i * 0.01 - 0.09, k++));
            lefts.push_back(randomImage(64, 48, 10 + f));
            rights.push_back(randomImage(64, 48, 20 + f));
            w.writeStereo(100.0 + f * 0.1, lefts.back(), rights.back());
        }
        w.writeImu(imuSample(100.25, k++));  // after the last frame: never yielded
        w.close();
    }
    auto src = openRawlog(dir / "rt.rawlog");
    EXPECT_NEAR(src->rig().left.fy, 51.0, 1e-12);
    EXPECT_NEAR(src->rig().left.dist[3], -0.0005, 1e-15);
    EXPECT_LT(core::translationDistance(src->rig().T_body_left, rig.T_body_left), 1e-12);
    EXPECT_LT(core::rotationDistanceRad(src->rig().T_left_right, rig.T_left_right), 1e-12);
    StereoFrame frame;
    for (int f = 0; f < 3; ++f)
    {
        ASSERT_TRUE(src->next(frame));
        EXPECT_EQ(frame.index, static_cast<size_t>(f));
        EXPECT_NEAR(frame.timestamp, 100.0 + f * 0.1, 1e-6);
        ASSERT_EQ(frame.left.type(), CV_8UC1);
        EXPECT_EQ(cv::norm(frame.left, lefts[f], cv::NORM_INF), 0.0);
        EXPECT_EQ(cv::norm(frame.right, rights[f], cv::NORM_INF), 0.0);
        ASSERT_EQ(frame.imu.size(), 10u);
        EXPECT_NEAR(frame.imu.back().t, frame.timestamp, 1e-6);
        EXPECT_DOUBLE_EQ(frame.imu.front().acc.x(), 0.1 * (f * 10));
        EXPECT_FALSE(frame.T_world_cam0.has_value());
    }
    EXPECT_FALSE(src->next(frame));
    EXPECT_TRUE(src->warnings().empty());
}

// A rawlog whose last entry is an action collection without the sensory frame that should follow it (recording
// stopped between the two; four of MRPT's own sample rawlogs end so): CRawlog ends there, and so does the reader,
// with a warning, after every frame before it.
TEST(RawlogWriter, FileEndingAfterAnActionCollectionReadsToItsEndWithAWarning)
{
    TempDir dir;
    const std::string path = dir / "ends_after_action.rawlog";  // its images: ends_after_action_Images/
    {
        RawlogWriter w(path, smallRig());
        for (int f = 0; f < 3; ++f)
        {
            for (int i = 0; i < 10; ++i) w.writeImu(imuSample(100.0 + f * 0.1 + i * 0.01 - 0.09, f * 10 + i));
            w.writeStereo(100.0 + f * 0.1, randomImage(64, 48, 10 + f), randomImage(64, 48, 20 + f));
        }
        w.close();
    }
    {
        // The written (compressed) file's objects, then the action, in a plain rawlog of the same name.
        std::string bytes(1 << 20, '\0');
        {
            mrpt::io::CFileGZInputStream in(path);
            bytes.resize(in.Read(bytes.data(), bytes.size()));
        }
        ASSERT_LT(bytes.size(), size_t(1 << 20));
        mrpt::io::CFileOutputStream out(path);
        out.Write(bytes.data(), bytes.size());
        mrpt::serialization::archiveFrom(out) << quasiloc::dataset::test::odometryActions();
    }
    auto src = openRawlog(path);
    StereoFrame frame;
    int frames = 0;
    while (src->next(frame)) ++frames;
    EXPECT_EQ(frames, 3);
    const auto warnings = src->warnings();
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("ends after an action collection without its sensory frame"), std::string::npos);
}

TEST(RawlogWriter, RejectsImagesOfWrongSizeOrType)
{
    TempDir dir;
    RawlogWriter w(dir / "bad.rawlog", smallRig());
    EXPECT_THROW(w.writeStereo(1.0, randomImage(63, 48, 1), randomImage(64, 48, 2)), core::InputError);
    cv::Mat colour(48, 64, CV_8UC3, cv::Scalar(1, 2, 3));
    EXPECT_THROW(w.writeStereo(1.0, randomImage(64, 48, 1), colour), core::InputError);

    const std::string good = dir / "good.png", small = dir / "small.png", rgb = dir / "rgb.png",
                      text = dir / "text.png";
    cv::imwrite(good, randomImage(64, 48, 1));
    cv::imwrite(small, randomImage(32, 48, 1));
    cv::imwrite(rgb, colour);
    std::ofstream(text) << "not an image";
    test::expectInputErrorMentioning([&] { w.writeStereoFromPngFiles(2.0, good, small); }, small);
    test::expectInputErrorMentioning([&] { w.writeStereoFromPngFiles(2.0, rgb, good); }, rgb);
    test::expectInputErrorMentioning([&] { w.writeStereoFromPngFiles(2.0, good, text); }, text);
    test::expectInputErrorMentioning([&] { w.writeStereoFromPngFiles(2.0, good, dir / "missing.png"); }, "missing.png");
    w.writeStereoFromPngFiles(2.0, good, good);
    EXPECT_THROW(w.writeStereoFromPngFiles(2.0, good, good), core::InputError);  // same timestamp twice
    EXPECT_EQ(w.numStereo(), 1u);
}
