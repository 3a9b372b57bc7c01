// Regression tests for what fuzzing the dataset readers found (fuzz/, docs/fuzzing.md).
#include <gtest/gtest.h>
#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservation3DScene.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/serialization/CArchive.h>
#include <sys/resource.h>

#include <cstdint>
#include <fstream>
#include <iostream>
#include <iterator>
#include <quasiloc/core/error.h>
#include <quasiloc/dataset/frame_source.h>
#include <quasiloc/dataset/timestamps.h>
#include <stdexcept>
#include <vector>

#include "test_helpers.h"

using namespace quasiloc;
using namespace quasiloc::dataset;
using quasiloc::dataset::test::odometryActions;
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

// ---------------------------------------------------------------------------------------------------------------
// Findings inside MRPT's deserialization (fuzz_rawlog; docs/fuzzing.md, finding 10): MRPT allocated what a length
// field said, decoded embedded JPEGs with libjpeg's exit(1) handler, and failed on truncation only after the
// allocation. The reader now parses the classes it uses itself (rawlog_entries.h); each case is an InputError naming
// the file, the entry and the field.
namespace
{
std::string fileBytes(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void writeFileBytes(const std::string& path, const std::string& bytes)
{
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

void putU32(std::string& bytes, size_t at, std::uint32_t value)
{
    for (int i = 0; i < 4; ++i) bytes[at + i] = char((value >> (8 * i)) & 0xFF);
}

/** Offset of the uint32 length stored before the string `text` (MRPT's std::string layout). */
size_t lengthFieldOf(const std::string& bytes, const std::string& text)
{
    const size_t at = bytes.find(text);
    EXPECT_NE(at, std::string::npos) << "'" << text << "' not in the file: MRPT's layout changed";
    EXPECT_GE(at, 4u);
    return at - 4;
}

enum class Images
{
    EmbeddedGray,
    EmbeddedJpeg,
    External
};

/** Entry 0: an IMU observation labelled "imu_label"; entry 1: a 16x12 stereo observation (camera name
 *  "cam_name") with the images as asked (external: "left_name.png" / "right_name.png", not written). */
void writeSmallRawlog(const std::string& path, Images images)
{
    mrpt::io::CFileOutputStream out(path);
    auto arch = mrpt::serialization::archiveFrom(out);
    auto imu = mrpt::obs::CObservationIMU::Create();
    imu->sensorLabel = "imu_label";
    imu->timestamp = mrptTimeFromNs(999'000'000);
    for (size_t i = 0; i < mrpt::obs::COUNT_IMU_DATA_FIELDS; ++i)
        imu->set(static_cast<mrpt::obs::TIMUDataIndex>(i), 0.5);
    arch << *imu;
    auto stereo = mrpt::obs::CObservationStereoImages::Create();
    stereo->timestamp = mrptTimeFromNs(1'000'000'000);
    auto cam = core::CameraModel::pinhole(16, 12, 10, 10, 8, 6).toTCamera();
    cam.cameraName = "cam_name";
    stereo->leftCamera = stereo->rightCamera = cam;
    stereo->rightCameraPose = mrpt::poses::CPose3DQuat(mrpt::poses::CPose3D(0.1, 0, 0, 0, 0, 0));
    stereo->hasImageRight = true;
    const bool raw_colour = mrpt::img::CImage::DISABLE_JPEG_COMPRESSION();
    if (images == Images::External)
    {
        stereo->imageLeft.setExternalStorage("left_name.png");
        stereo->imageRight.setExternalStorage("right_name.png");
    }
    else
    {
        cv::Mat img(12, 16, images == Images::EmbeddedJpeg ? CV_8UC3 : CV_8UC1, cv::Scalar(50, 90, 130));
        stereo->imageLeft = mrpt::img::CImage(img, mrpt::img::DEEP_COPY);
        stereo->imageRight = mrpt::img::CImage(img, mrpt::img::DEEP_COPY);
        mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(images != Images::EmbeddedJpeg);
    }
    arch << *stereo;
    mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(raw_colour);
}

/** Reads every frame; expects an InputError whose message names the file and contains each of `needles`. */
void expectRawlogInputError(const std::string& path, const std::vector<std::string>& needles)
{
    try
    {
        auto source = openRawlog(path);
        StereoFrame frame;
        while (source->next(frame))
        {}
        ADD_FAILURE() << "no error reading " << path;
    }
    catch (const core::InputError& e)
    {
        const std::string what = e.what();
        std::cout << "  expected InputError: " << what << std::endl;
        EXPECT_NE(what.find(path), std::string::npos) << what;
        for (const auto& n : needles) EXPECT_NE(what.find(n), std::string::npos) << "'" << n << "' not in: " << what;
    }
}

/** `bytes` (a small rawlog) written to `path` with the uint32 length before `text` set to `length`, then read:
 *  expects expectRawlogInputError's error. */
void expectLengthFieldError(const std::string& path, std::string bytes, const std::string& text, std::uint32_t length,
                            const std::vector<std::string>& needles)
{
    putU32(bytes, lengthFieldOf(bytes, text), length);
    writeFileBytes(path, bytes);
    expectRawlogInputError(path, needles);
}
}  // namespace

// A sensor label whose length field says 4 GB: MRPT's operator>>(std::string) resized the string to it.
TEST(FuzzFindings, RawlogSensorLabelLengthBeyondTheBoundIsAnInputError)
{
    TempDir dir;
    const std::string path = dir / "label.rawlog";
    writeSmallRawlog(path, Images::EmbeddedGray);
    expectLengthFieldError(path, fileBytes(path), "imu_label", 0xFFFFFFF0u,
                           {"entry 0", "mrpt::obs::CObservationIMU", "sensorLabel", "4294967280 bytes"});
}

// TCamera::serializeFrom's camera name (found by fuzz_rawlog: 0.6 to 1.9 GB strings): a length within our bound but
// beyond the end of the file fails as truncated, before anything of that size is allocated.
TEST(FuzzFindings, RawlogCameraNameLongerThanTheFileIsTruncated)
{
    TempDir dir;
    const std::string path = dir / "camera.rawlog";
    writeSmallRawlog(path, Images::EmbeddedGray);
    const std::string bytes = fileBytes(path);
    expectLengthFieldError(path, bytes, "cam_name", 60'000,
                           {"entry 1", "leftCamera", "cameraName", "truncated", "60000"});
    expectLengthFieldError(path, bytes, "cam_name", 0x7FFFFFFF,
                           {"entry 1", "cameraName", "2147483647 bytes, more than"});
}

// The external image file name's length.
TEST(FuzzFindings, RawlogExternalImageFileNameLengthIsChecked)
{
    TempDir dir;
    const std::string path = dir / "external.rawlog";
    writeSmallRawlog(path, Images::External);
    expectLengthFieldError(path, fileBytes(path), "left_name.png", 0xFFFFFFFFu,
                           {"entry 1", "imageLeft", "external file name", "more than"});
}

// The length byte of a class name (CArchive::internal_ReadObject's header) and a class name that is not MRPT's.
TEST(FuzzFindings, RawlogClassNameLengthAndUnknownClassAreInputErrors)
{
    TempDir dir;
    const std::string path = dir / "class.rawlog";
    writeSmallRawlog(path, Images::EmbeddedGray);
    const std::string good = fileBytes(path);
    const std::string image_class = "mrpt::img::CImage";
    const size_t at = good.find(image_class);
    ASSERT_NE(at, std::string::npos);
    ASSERT_EQ(static_cast<unsigned char>(good[at - 1]), 0x80 | image_class.size());
    std::string bytes = good;
    bytes[at - 1] = char(0xFF);  // 127 bytes
    writeFileBytes(path, bytes);
    expectRawlogInputError(path, {"entry 1", "imageLeft", "class name of 127 bytes"});
    // Finding 13: a class name of 0 bytes read 0 bytes into an empty vector's null data() (UBSan: memcpy to null).
    bytes = good;
    bytes[at - 1] = char(0x80);
    writeFileBytes(path, bytes);
    expectRawlogInputError(path, {"entry 1", "imageLeft", "class name of 0 bytes"});
    bytes = good;
    bytes[at + image_class.size() - 1] = 'X';  // mrpt::img::CImagX
    writeFileBytes(path, bytes);
    expectRawlogInputError(path, {"entry 1", "imageLeft", "'mrpt::img::CImagX' is not registered in MRPT"});
}

// An embedded image of 100000 x 100000 pixels (MRPT: CImage::resize -> cv::Mat::create of 10 GB, up to 3.6e18
// bytes seen by the fuzzer).
TEST(FuzzFindings, RawlogHugeEmbeddedImageSizeIsAnInputError)
{
    TempDir dir;
    const std::string path = dir / "huge.rawlog";
    writeSmallRawlog(path, Images::EmbeddedGray);
    std::string bytes = fileBytes(path);
    // CImage version 9, gray: header, version, external flag, colour flag, then width and height (int32).
    const size_t at = bytes.find("mrpt::img::CImage") + std::string("mrpt::img::CImage").size();
    ASSERT_EQ(bytes[at], 9) << "MRPT's CImage version changed";
    ASSERT_EQ(bytes[at + 3], 16) << "MRPT's CImage layout changed";
    putU32(bytes, at + 3, 100'000);
    putU32(bytes, at + 7, 100'000);
    writeFileBytes(path, bytes);
    expectRawlogInputError(path, {"entry 1", "imageLeft", "100000x100000 is beyond"});
}

// A corrupt embedded JPEG: MRPT decodes it with libjpeg's default error handler, which calls exit(1) (this test's
// process would end). The frame's JPEG has its sample precision set to 13 bits, which libjpeg rejects.
TEST(FuzzFindings, RawlogCorruptEmbeddedJpegIsAnInputErrorNotExit)
{
    TempDir dir;
    const std::string path = dir / "jpeg.rawlog";
    writeSmallRawlog(path, Images::EmbeddedJpeg);
    std::string bytes = fileBytes(path);
    const size_t sof = bytes.find("\xFF\xC0");
    ASSERT_NE(sof, std::string::npos) << "no baseline JPEG frame header: MRPT's JPEG storage changed";
    ASSERT_EQ(bytes[sof + 4], 8);  // sample precision
    std::string corrupt = bytes;
    corrupt[sof + 4] = 13;
    writeFileBytes(path, corrupt);
    expectRawlogInputError(path, {"entry 1", "left image", "cannot decode the embedded JPEG"});

    // A frame header announcing 65000 x 65000 pixels: rejected before the decoder allocates 12 GB.
    corrupt = bytes;
    corrupt[sof + 5] = corrupt[sof + 7] = char(0xFD);
    corrupt[sof + 6] = corrupt[sof + 8] = char(0xE8);
    writeFileBytes(path, corrupt);
    expectRawlogInputError(path, {"entry 1", "left image", "65000x65000 pixels is beyond"});

    writeFileBytes(path, bytes);  // the intact file decodes (through OpenCV)
    auto source = openRawlog(path);
    StereoFrame frame;
    ASSERT_TRUE(source->next(frame));
    EXPECT_EQ(frame.left.type(), CV_8UC1);
    EXPECT_NEAR(frame.left.at<unsigned char>(5, 5), 0.114 * 50 + 0.587 * 90 + 0.299 * 130, 3);
}

// A file cut anywhere: a clean end when the cut falls between entries, otherwise an InputError ("truncated", with
// the entry), never a crash or an allocation from the half-read entry.
TEST(FuzzFindings, RawlogTruncatedAnywhereIsAnInputErrorOrACleanEnd)
{
    TempDir dir;
    const std::string path = dir / "cut.rawlog";
    writeSmallRawlog(path, Images::EmbeddedGray);
    const std::string bytes = fileBytes(path);
    const size_t entry1 = bytes.find("mrpt::obs::CObservationStereoImages") - 1;
    size_t clean_ends = 0, errors = 0;
    for (size_t cut = 0; cut < bytes.size(); ++cut)
    {
        writeFileBytes(path, bytes.substr(0, cut));
        try
        {
            auto source = openRawlog(path);  // needs a stereo frame: only the whole file opens
            StereoFrame frame;
            while (source->next(frame))
            {}
            ADD_FAILURE() << "a rawlog cut at " << cut << " of " << bytes.size() << " bytes read without error";
        }
        catch (const core::InputError& e)
        {
            const std::string what = e.what();
            if (what.find("truncated") != std::string::npos)
            {
                ++errors;
                EXPECT_NE(what.find(cut < entry1 ? "entry 0" : "entry 1"), std::string::npos) << what;
            }
            else
            {
                ++clean_ends;  // cut at 0 or between the entries: no stereo observation
                EXPECT_NE(what.find("holds no CObservationStereoImages"), std::string::npos) << what;
            }
        }
    }
    EXPECT_EQ(clean_ends, 2u);
    EXPECT_EQ(errors, bytes.size() - 2);
}

// ---------------------------------------------------------------------------------------------------------------
// Objects of the classes the reader does not parse, which MRPT still reads (docs/fuzzing.md, finding 11): MRPT read
// them in this process, so a corrupt one allocated what a length field said, ended the process with exit(1) or
// crashed it. They are read in a child process now (isolated_object_reader.h); each case is an InputError naming the
// file, the entry, the object's byte offset and its class.
namespace
{
mrpt::obs::CObservationStereoImages::Ptr smallStereo(std::int64_t t_ns)
{
    auto stereo = mrpt::obs::CObservationStereoImages::Create();
    stereo->timestamp = mrptTimeFromNs(t_ns);
    stereo->leftCamera = stereo->rightCamera = core::CameraModel::pinhole(16, 12, 10, 10, 8, 6).toTCamera();
    stereo->rightCameraPose = mrpt::poses::CPose3DQuat(mrpt::poses::CPose3D(0.1, 0, 0, 0, 0, 0));
    const cv::Mat img(12, 16, CV_8UC1, cv::Scalar(50));
    stereo->imageLeft = stereo->imageRight = mrpt::img::CImage(img, mrpt::img::DEEP_COPY);
    stereo->hasImageRight = true;
    return stereo;
}

/** Entry 0: a stereo observation; entry 1: `object`. Returns the file's bytes. */
std::string writeStereoThen(const std::string& path, const mrpt::serialization::CSerializable& object)
{
    {
        mrpt::io::CFileOutputStream out(path);
        auto arch = mrpt::serialization::archiveFrom(out);
        arch << *smallStereo(1'000'000'000) << object;
    }
    return fileBytes(path);
}
}  // namespace

// A 2D scan whose beam count says 2^31: MRPT's CObservation2DRangeScan::serializeFrom resizes its arrays to it
// (18 GB, zeroed). In the child the allocation fails at its 4 GiB budget; MRPT's aligned allocator then returns a
// null pointer (mrpt::aligned_malloc does not throw), which the vector writes through: SIGSEGV. In this process it
// was 18 GB of memory touched, or the same crash under a memory limit.
TEST(FuzzFindings, RawlogUnparsedObservationWithAHugeLengthIsAnInputError)
{
    TempDir dir;
    const std::string path = dir / "scan.rawlog";
    mrpt::obs::CObservation2DRangeScan scan;
    scan.resizeScan(3);
    for (size_t i = 0; i < 3; ++i) scan.setScanRange(i, 1.25f * float(i + 1));
    std::string bytes = writeStereoThen(path, scan);
    const float first = 1.25f;
    const size_t at = bytes.find(std::string(reinterpret_cast<const char*>(&first), 4));
    ASSERT_NE(at, std::string::npos);
    ASSERT_EQ(bytes[at - 4], 3) << "MRPT's CObservation2DRangeScan layout changed";
    putU32(bytes, at - 4, 0x80000000u);
    writeFileBytes(path, bytes);
    expectRawlogInputError(path,
                           {"entry 1", "MRPT could not read the object of class mrpt::obs::CObservation2DRangeScan",
                            "the reading process ended with signal 11 (SIGSEGV)"});
}

// Found by fuzz_rawlog (24 times in the 300 s run before this change; ASan: SEGV inside libmrpt-obs): an action whose
// estimation method is not odometry, so that MRPT reads its pose PDF as an object, followed by an object that is no
// CPosePDF (here the CPose2D of the odometry): ReadObject<CPosePDF> gives a null pointer, which
// CActionRobotMovement2D::serializeFrom clones through (its deepcopy_poly_ptr).
TEST(FuzzFindings, RawlogActionWhoseMrptReaderCrashesIsAnInputError)
{
    TempDir dir;
    const std::string path = dir / "action.rawlog";
    {
        mrpt::io::CFileOutputStream out(path);
        auto arch = mrpt::serialization::archiveFrom(out);
        const mrpt::obs::CActionCollection actions = odometryActions();
        mrpt::obs::CSensoryFrame frame;
        frame.insert(smallStereo(1'000'000'000));
        arch << actions << frame;
    }
    std::string bytes = fileBytes(path);
    const std::string name = "mrpt::obs::CActionRobotMovement2D";
    const size_t at = bytes.find(name) + name.size();  // version, then the estimation method (int32)
    ASSERT_EQ(bytes[at], 7) << "MRPT's CActionRobotMovement2D version changed";
    ASSERT_EQ(bytes.substr(at + 1, 4), std::string(4, '\0')) << "not emOdometry";
    bytes[at + 1] = 1;  // emScan2DMatching: the PDF is read as an object
    writeFileBytes(path, bytes);
    expectRawlogInputError(path, {"entry 0", "mrpt::obs::CActionCollection > action 0",
                                  "MRPT could not read the object of class mrpt::obs::CActionRobotMovement2D",
                                  "the reading process ended with signal 11 (SIGSEGV)"});
}

// A corrupt JPEG inside an observation class we do not parse (CObservationImage): MRPT's CImage decodes it with
// libjpeg's default error handler, which calls exit(1).
TEST(FuzzFindings, RawlogUnparsedObjectWhoseReaderCallsExitIsAnInputError)
{
    TempDir dir;
    const std::string path = dir / "image.rawlog";
    mrpt::obs::CObservationImage image;
    image.image = mrpt::img::CImage(cv::Mat(12, 16, CV_8UC3, cv::Scalar(50, 90, 130)), mrpt::img::DEEP_COPY);
    const bool raw_colour = mrpt::img::CImage::DISABLE_JPEG_COMPRESSION();
    mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(false);  // colour stored as JPEG
    std::string bytes = writeStereoThen(path, image);
    mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(raw_colour);
    const size_t sof = bytes.find("\xFF\xC0", bytes.find("CObservationImage"));
    ASSERT_NE(sof, std::string::npos) << "no baseline JPEG frame header: MRPT's JPEG storage changed";
    ASSERT_EQ(bytes[sof + 4], 8);  // sample precision
    bytes[sof + 4] = 13;
    writeFileBytes(path, bytes);
    expectRawlogInputError(path, {"entry 1", "MRPT could not read the object of class mrpt::obs::CObservationImage",
                                  "the reading process ended with exit status 1"});
}

// A 3D scene whose objects nest 100,000 deep (a CSetOfObjects in a CSetOfObjects ...; a well-formed object): MRPT's
// recursive reader overflows the stack (SIGSEGV).
TEST(FuzzFindings, RawlogDeeplyNestedUnparsedObjectIsAnInputErrorNotAStackOverflow)
{
    rlimit stack{};
    ASSERT_EQ(::getrlimit(RLIMIT_STACK, &stack), 0);
    if (stack.rlim_cur == RLIM_INFINITY || stack.rlim_cur > (64u << 20))
        GTEST_SKIP() << "the stack may grow beyond 64 MiB here: 100,000 levels may not overflow it";
    // Three levels written by MRPT; the middle one (header, CRenderizable fields, a count of 1) repeats.
    auto inner = mrpt::opengl::CSetOfObjects::Create(), middle = mrpt::opengl::CSetOfObjects::Create();
    auto outer = mrpt::opengl::CSetOfObjects::Create();
    middle->insert(inner);
    outer->insert(middle);
    mrpt::obs::CObservation3DScene scene;
    scene.scene = mrpt::opengl::COpenGLScene::Create();
    scene.scene->insert(outer);
    TempDir dir;
    const std::string path = dir / "nested.rawlog";
    const std::string bytes = writeStereoThen(path, scene);
    const std::string name = "mrpt::opengl::CSetOfObjects";
    const size_t p0 = bytes.find(name) - 1, p1 = bytes.find(name, p0 + 2) - 1, p2 = bytes.find(name, p1 + 2) - 1;
    const std::string level = bytes.substr(p1, p2 - p1);
    ASSERT_EQ(bytes.substr(p0, p1 - p0), level) << "MRPT's CSetOfObjects layout changed";
    const size_t inner_end = p2 + level.size() + 1;  // the inner set: a count of 0, then its end flag
    ASSERT_EQ(static_cast<unsigned char>(bytes[inner_end - 1]), 0x88);
    std::string nested = bytes.substr(0, p2);
    for (int i = 0; i < 100'000; ++i) nested += level;
    nested += bytes.substr(p2, inner_end - p2) + std::string(100'000, '\x88') + bytes.substr(inner_end);
    writeFileBytes(path, nested);
    expectRawlogInputError(path, {"entry 1", "MRPT could not read the object of class mrpt::obs::CObservation3DScene",
                                  "the reading process ended with signal 11 (SIGSEGV)"});
}

// A file cut anywhere, with objects MRPT reads (an action, observations in a sensory frame and at the top level): a
// clean end between entries, otherwise "truncated" naming the entry, and inside an object MRPT reads, its class.
TEST(FuzzFindings, RawlogTruncatedInsideAnUnparsedObjectIsAnInputError)
{
    TempDir dir;
    const std::string path = dir / "cut.rawlog";
    {
        mrpt::io::CFileOutputStream out(path);
        auto arch = mrpt::serialization::archiveFrom(out);
        const mrpt::obs::CActionCollection actions = odometryActions();
        mrpt::obs::CSensoryFrame frame;
        auto odometry = mrpt::obs::CObservationOdometry::Create();
        odometry->timestamp = mrptTimeFromNs(900'000'000);
        frame.insert(odometry);
        frame.insert(smallStereo(1'000'000'000));
        arch << actions << frame << *odometry;
    }
    const std::string bytes = fileBytes(path);
    size_t clean_ends = 0, truncated = 0, inside_unparsed = 0;
    for (size_t cut = 0; cut < bytes.size(); ++cut)
    {
        writeFileBytes(path, bytes.substr(0, cut));
        try
        {
            auto source = openRawlog(path);
            StereoFrame frame;
            while (source->next(frame))
            {}
            ++clean_ends;  // cut after the sensory frame, before the last odometry
        }
        catch (const core::InputError& e)
        {
            const std::string what = e.what();
            if (what.find("holds no CObservationStereoImages") != std::string::npos)
            {
                ++clean_ends;  // cut at 0, or after the action collection (CRawlog ends there too)
                continue;
            }
            ++truncated;
            EXPECT_NE(what.find("truncated"), std::string::npos) << what;
            if (what.find("the file ends inside the object of class mrpt::obs::C") != std::string::npos)
                ++inside_unparsed;
        }
    }
    EXPECT_EQ(clean_ends, 3u);
    EXPECT_EQ(truncated, bytes.size() - 3);
    EXPECT_GT(inside_unparsed, 100u) << "the action and the odometry observations are read by MRPT";
}
