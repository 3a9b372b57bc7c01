// Regression tests for what fuzzing the dataset readers found (fuzz/, docs/fuzzing.md).
#include <gtest/gtest.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdint>
#include <fstream>
#include <iterator>
#include <quasiloc/core/error.h>
#include <quasiloc/dataset/frame_source.h>
#include <quasiloc/dataset/timestamps.h>
#include <stdexcept>

#include "test_helpers.h"

using namespace quasiloc;
using namespace quasiloc::dataset;
using quasiloc::dataset::test::TempDir;

// fuzz_rawlog: MRPT reads CObservationIMU::dataIsPresent as raw bytes, so a corrupt rawlog can hold a flag byte
// that is no valid bool (177 here); CObservationIMU::has() loading it is undefined behaviour (UBSan: "load of value
// 177, which is not a valid value for type bool"). The reader now reads any non-zero byte as "present".
TEST(FuzzFindings, RawlogImuFlagsThatAreNotValidBoolsReadAsPresent)
{
    TempDir dir;
    const std::string path = dir / "flags.rawlog";
    {
        mrpt::io::CFileOutputStream out(path);  // uncompressed: the reader's gzip stream reads it as is
        auto arch = mrpt::serialization::archiveFrom(out);
        auto imu = mrpt::obs::CObservationIMU::Create();
        imu->timestamp = mrptTimeFromNs(999'000'000);
        for (size_t i = 0; i < mrpt::obs::COUNT_IMU_DATA_FIELDS; ++i)
            imu->set(static_cast<mrpt::obs::TIMUDataIndex>(i), 0.25 * double(i));
        arch << *imu;
        auto stereo = mrpt::obs::CObservationStereoImages::Create();
        stereo->timestamp = mrptTimeFromNs(1'000'000'000);
        stereo->leftCamera = stereo->rightCamera = core::CameraModel::pinhole(16, 12, 10, 10, 8, 6).toTCamera();
        stereo->rightCameraPose = mrpt::poses::CPose3DQuat(mrpt::poses::CPose3D(0.1, 0, 0, 0, 0, 0));
        const cv::Mat img(12, 16, CV_8UC1, cv::Scalar(50));
        stereo->imageLeft = mrpt::img::CImage(img, mrpt::img::DEEP_COPY);
        stereo->imageRight = mrpt::img::CImage(img, mrpt::img::DEEP_COPY);
        stereo->hasImageRight = true;
        arch << *stereo;
    }
    // The flags are stored as one byte each: the run of COUNT_IMU_DATA_FIELDS ones becomes 177s.
    std::string bytes;
    {
        std::ifstream in(path, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    const size_t at = bytes.find(std::string(mrpt::obs::COUNT_IMU_DATA_FIELDS, '\x01'));
    ASSERT_NE(at, std::string::npos) << "MRPT's CObservationIMU layout changed: no run of flag bytes";
    for (size_t i = 0; i < mrpt::obs::COUNT_IMU_DATA_FIELDS; ++i) bytes[at + i] = char(177);
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;

    auto source = openRawlog(path);
    StereoFrame frame;
    ASSERT_TRUE(source->next(frame));
    ASSERT_EQ(frame.imu.size(), 1u);
    EXPECT_DOUBLE_EQ(frame.imu[0].acc.x(), 0.25 * mrpt::obs::IMU_X_ACC);
    EXPECT_DOUBLE_EQ(frame.imu[0].gyro.z(), 0.25 * mrpt::obs::IMU_WZ);
}

// fuzz_rawlog, same cause: CObservationStereoImages::hasImageRight read as a raw byte (5 here).
TEST(FuzzFindings, RawlogHasImageRightThatIsNotAValidBoolReadsAsPresent)
{
    TempDir dir;
    const std::string path = dir / "right.rawlog";
    {
        mrpt::io::CFileOutputStream out(path);
        auto arch = mrpt::serialization::archiveFrom(out);
        auto stereo = mrpt::obs::CObservationStereoImages::Create();
        stereo->timestamp = mrptTimeFromNs(1'000'000'000);
        stereo->leftCamera = stereo->rightCamera = core::CameraModel::pinhole(16, 12, 10, 10, 8, 6).toTCamera();
        stereo->rightCameraPose = mrpt::poses::CPose3DQuat(mrpt::poses::CPose3D(0.1, 0, 0, 0, 0, 0));
        const cv::Mat img(12, 16, CV_8UC1, cv::Scalar(50));
        stereo->imageLeft = mrpt::img::CImage(img, mrpt::img::DEEP_COPY);
        stereo->imageRight = mrpt::img::CImage(img, mrpt::img::DEEP_COPY);
        stereo->hasImageRight = true;
        arch << *stereo;
    }
    std::string bytes;
    {
        std::ifstream in(path, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    // hasImageDisparity and hasImageRight are the two bytes before the right image's object header.
    const std::string image_class = "mrpt::img::CImage";
    const size_t left = bytes.find(image_class), right = bytes.find(image_class, left + 1);
    ASSERT_NE(right, std::string::npos) << "MRPT's CObservationStereoImages layout changed";
    ASSERT_EQ(bytes[right - 2], '\x01') << "MRPT's CObservationStereoImages layout changed";
    bytes[right - 2] = 5;
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;

    auto source = openRawlog(path);
    StereoFrame frame;
    ASSERT_TRUE(source->next(frame));
    EXPECT_EQ(frame.right.cols, 16);
}

// fuzz_rawlog: an observation's timestamp is any int64 tick count in a corrupt rawlog; converting 5.7e18 ticks to
// nanoseconds overflowed int64 (UBSan: "signed integer overflow" in mrptTimeToNs). The reader now rejects such a
// time with an InputError naming the file and entry; mrptTimeToNs throws std::out_of_range.
TEST(FuzzFindings, RawlogTimestampBeyondInt64NanosecondsIsAnInputError)
{
    const mrpt::Clock::time_point far(mrpt::Clock::duration(5667085633192391535));
    EXPECT_THROW(mrptTimeToNs(far), std::out_of_range);
    EXPECT_FALSE(mrptTimeToNsChecked(far).has_value());
    EXPECT_FALSE(mrptTimeToNsChecked(mrpt::Clock::time_point(mrpt::Clock::duration(INT64_MIN))).has_value());
    EXPECT_EQ(mrptTimeToNs(mrptTimeFromNs(1'000'000'000)), 1'000'000'000);

    TempDir dir;
    const std::string path = dir / "far.rawlog";
    {
        mrpt::io::CFileOutputStream out(path);
        auto arch = mrpt::serialization::archiveFrom(out);
        auto imu = mrpt::obs::CObservationIMU::Create();
        imu->timestamp = far;
        for (size_t i = 0; i < mrpt::obs::COUNT_IMU_DATA_FIELDS; ++i)
            imu->set(static_cast<mrpt::obs::TIMUDataIndex>(i), 0.0);
        arch << *imu;
    }
    try
    {
        auto source = openRawlog(path);
        StereoFrame frame;
        source->next(frame);
        FAIL() << "a timestamp 5.7e18 ticks from MRPT's epoch was accepted";
    }
    catch (const core::InputError& e)
    {
        const std::string what = e.what();
        EXPECT_NE(what.find("far.rawlog"), std::string::npos) << what;
        EXPECT_NE(what.find("entry 0"), std::string::npos) << what;
        EXPECT_NE(what.find("292 years"), std::string::npos) << what;
    }
}
