// Valid rawlogs read identically through openRawlog before and after the validating entry scanner
// (rawlog_entries.h): same rig, frames (timestamps, pixels), IMU samples and warnings. Each test
// reads a real file and compares a digest of everything the reader yields with the digest that the reader
// produced before the scanner existed (MRPT's CRawlog::getActionObservationPairOrObservation deserializing
// every entry), recorded here as a constant.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CObservationGPS.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3DQuat.h>
#include <mrpt/serialization/CArchive.h>

#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <quasiloc/dataset/euroc.h>
#include <quasiloc/dataset/euroc_conversion.h>
#include <quasiloc/dataset/frame_source.h>
#include <quasiloc/dataset/rawlog_writer.h>
#include <quasiloc/dataset/timestamps.h>
#include <sstream>

#include "rawlog_entries.h"
#include "test_helpers.h"

using namespace quasiloc;
using namespace quasiloc::dataset;
using quasiloc::dataset::test::TempDir;
namespace fs = std::filesystem;

namespace
{
std::uint64_t fnv1a(const void* data, size_t n, std::uint64_t h = 1469598103934665603ULL)
{
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ULL;
    return h;
}

std::string g(double v)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

void describeCamera(std::ostream& os, const core::CameraModel& c)
{
    os << c.width << "x" << c.height << " " << g(c.fx) << " " << g(c.fy) << " " << g(c.cx) << " " << g(c.cy) << " "
       << int(c.model);
    for (double d : c.dist) os << " " << g(d);
    os << "\n";
}

void describePose(std::ostream& os, const mrpt::poses::CPose3D& p)
{
    for (int r = 0; r < 3; ++r)
    {
        os << g(p.m_coords[r]);
        for (int c = 0; c < 3; ++c) os << " " << g(p.getRotationMatrix()(r, c));
        os << ";";
    }
    os << "\n";
}

void describeImage(std::ostream& os, const cv::Mat& m)
{
    const cv::Mat c = m.isContinuous() ? m : m.clone();
    os << m.cols << "x" << m.rows << " t" << m.type() << " #" << fnv1a(c.data, c.total() * c.elemSize()) << "\n";
}

struct Digest
{
    size_t frames = 0, imu_samples = 0;
    std::uint64_t hash = 0;
    std::string text;  // the described content, printed on a mismatch
};

/** Everything openRawlog yields for `path`, as text and its hash. */
Digest digestOf(const std::string& path)
{
    std::ostringstream os;
    Digest d;
    auto src = openRawlog(path);
    describeCamera(os, src->rig().left);
    describeCamera(os, src->rig().right);
    describePose(os, src->rig().T_left_right);
    describePose(os, src->rig().T_body_left);
    StereoFrame f;
    while (src->next(f))
    {
        ++d.frames;
        os << "frame " << f.index << " t=" << g(f.timestamp) << " gt=" << f.T_world_cam0.has_value() << "\n";
        describeImage(os, f.left);
        describeImage(os, f.right);
        for (const auto& s : f.imu)
        {
            ++d.imu_samples;
            os << " imu " << g(s.t);
            for (int k = 0; k < 3; ++k) os << " " << g(s.acc[k]) << " " << g(s.gyro[k]);
            os << "\n";
        }
    }
    for (const auto& w : src->warnings()) os << "warning: " << w << "\n";
    d.text = os.str();
    d.hash = fnv1a(d.text.data(), d.text.size());
    return d;
}

void expectDigest(const std::string& path, size_t frames, size_t imu_samples, std::uint64_t hash)
{
    const Digest d = digestOf(path);
    EXPECT_EQ(d.frames, frames);
    EXPECT_EQ(d.imu_samples, imu_samples);
    EXPECT_EQ(d.hash, hash) << "digest 0x" << std::hex << d.hash << " of:\n" << d.text;
}

mrpt::obs::CObservationStereoImages::Ptr stereoObs(const core::StereoRig& rig, std::int64_t t_ns)
{
    auto s = mrpt::obs::CObservationStereoImages::Create();
    s->sensorLabel = "cam";
    s->timestamp = mrptTimeFromNs(t_ns);
    s->leftCamera = rig.left.toTCamera();
    s->rightCamera = rig.right.toTCamera();
    s->rightCameraPose = mrpt::poses::CPose3DQuat(rig.T_left_right);
    s->cameraPose = mrpt::poses::CPose3DQuat(rig.T_body_left);
    s->hasImageRight = true;
    return s;
}

mrpt::obs::CObservationIMU::Ptr imuObs(std::int64_t t_ns, bool complete)
{
    using namespace mrpt::obs;
    auto imu = CObservationIMU::Create();
    imu->sensorLabel = "imu";
    imu->timestamp = mrptTimeFromNs(t_ns);
    for (auto i : {IMU_X_ACC, IMU_Y_ACC, IMU_Z_ACC, IMU_WX, IMU_WY, IMU_WZ})
        if (complete || i != IMU_WZ) imu->set(i, 0.125 * i + 1e-9 * double(t_ns % 1000));
    return imu;
}

cv::Mat readGray(const std::string& path) { return cv::imread(path, cv::IMREAD_UNCHANGED); }
}  // namespace

// A rawlog of our own writer (euroc2rawlog's conversion of the real EuRoC micro sequence): gz-compressed,
// external PNG images, 95 stereo observations and the sequence's IMU rows up to the last frame.
TEST(RawlogReadIdentity, EurocMicroConvertedByOurWriter)
{
    TempDir dir;
    Euroc2RawlogOptions o;
    o.input = test::microEurocFolder();
    o.output = dir / "micro.rawlog";
    convertEurocToRawlog(o);
    expectDigest(dir / "micro.rawlog", 95, 941, 0xd560c8b81dafba22ULL);
}

// A rawlog written by MRPT's own serialization in every layout and image storage the reader meets: a
// top-level object that is no observation, action collections (with an action of a class the reader does not
// read) followed by sensory frames, observation-only entries, embedded gray images, a colour image stored as
// JPEG, a colour image stored raw (MRPT's default since CImage::DISABLE_JPEG_COMPRESSION is true by default), a
// disparity image, a stereo observation without its right image, external PNG images, an observation class the reader
// ignores, an incomplete and a late IMU sample. The images are real (EuRoC micro frames 0-3). gz-compressed.
TEST(RawlogReadIdentity, MrptWrittenLayoutsWithEmbeddedImages)
{
    using namespace mrpt::obs;
    TempDir dir;
    const EurocSequence seq = readEurocSequence(test::microEurocFolder());
    const core::StereoRig& rig = seq.rig;
    ASSERT_GE(seq.pairs.size(), 4u);
    std::vector<cv::Mat> left, right;
    for (size_t k = 0; k < 4; ++k)
    {
        left.push_back(readGray(seq.pairs[k].left_png));
        right.push_back(readGray(seq.pairs[k].right_png));
        ASSERT_EQ(left.back().type(), CV_8UC1);
    }
    const std::string path = dir / "mrpt.rawlog";
    fs::create_directories(rawlogImagesFolder(path));
    {
        mrpt::io::CFileGZOutputStream out(path);
        auto arch = mrpt::serialization::archiveFrom(out);
        const std::int64_t t0 = 1'403'715'273'262'142'976LL;
        const std::int64_t ms = 1'000'000;
        arch << mrpt::poses::CPose3D(1, 2, 3, 0.1, 0.2, 0.3);  // no observation: skipped by the reader

        CActionCollection acts;
        CActionRobotMovement2D move;
        move.computeFromOdometry(mrpt::poses::CPose2D(0.1, 0, 0.01), CActionRobotMovement2D::TMotionModelOptions());
        acts.insert(move);
        arch << acts;
        CSensoryFrame sf;
        sf.insert(imuObs(t0 - 5 * ms, true));
        auto s0 = stereoObs(rig, t0);
        s0->imageLeft = mrpt::img::CImage(left[0], mrpt::img::DEEP_COPY);
        s0->imageRight = mrpt::img::CImage(right[0], mrpt::img::DEEP_COPY);
        sf.insert(s0);
        auto odo = CObservationOdometry::Create();
        odo->timestamp = mrptTimeFromNs(t0);
        sf.insert(odo);
        arch << sf;

        arch << CActionCollection();
        CSensoryFrame sf1;
        auto s1 = stereoObs(rig, t0 + 50 * ms);
        cv::Mat colour_left, colour_right;
        cv::cvtColor(left[1], colour_left, cv::COLOR_GRAY2BGR);
        cv::cvtColor(right[1], colour_right, cv::COLOR_GRAY2BGR);
        colour_left.col(10).setTo(cv::Scalar(200, 30, 90));  // not gray: the BGR -> gray conversion matters
        s1->imageLeft = mrpt::img::CImage(colour_left, mrpt::img::DEEP_COPY);
        s1->imageRight = mrpt::img::CImage(colour_right, mrpt::img::DEEP_COPY);
        sf1.insert(s1);
        sf1.insert(imuObs(t0 + 45 * ms, false));
        const bool raw_colour = mrpt::img::CImage::DISABLE_JPEG_COMPRESSION();
        mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(false);  // colour stored as JPEG
        arch << sf1;

        auto s2 = stereoObs(rig, t0 + 100 * ms);
        cv::cvtColor(left[2], colour_left, cv::COLOR_GRAY2BGR);
        cv::cvtColor(right[2], colour_right, cv::COLOR_GRAY2BGR);
        colour_right.row(7).setTo(cv::Scalar(5, 250, 60));
        s2->imageLeft = mrpt::img::CImage(colour_left, mrpt::img::DEEP_COPY);
        s2->imageRight = mrpt::img::CImage(colour_right, mrpt::img::DEEP_COPY);
        s2->hasImageDisparity = true;
        s2->imageDisparity = mrpt::img::CImage(cv::Mat(4, 6, CV_8UC1, cv::Scalar(3)), mrpt::img::DEEP_COPY);
        mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(true);  // colour stored raw
        arch << *s2;
        mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(raw_colour);

        arch << *imuObs(t0 + 120 * ms, true);
        auto no_right = stereoObs(rig, t0 + 130 * ms);
        no_right->imageLeft = mrpt::img::CImage(left[3], mrpt::img::DEEP_COPY);
        no_right->hasImageRight = false;
        arch << *no_right;

        auto s3 = stereoObs(rig, t0 + 150 * ms);
        cv::imwrite(rawlogImagesFolder(path) + "/l3.png", left[3]);
        cv::imwrite(rawlogImagesFolder(path) + "/r3.png", right[3]);
        s3->imageLeft.setExternalStorage("l3.png");
        s3->imageRight.setExternalStorage("r3.png");
        arch << *s3;
        arch << *imuObs(t0 + 60 * ms, true);  // older than frame 2, read after it: late
        arch << *imuObs(t0 + 200 * ms, true);
    }
    expectDigest(path, 4, 2, 0x6fd033202da1d006ULL);
}

// The layout of the fuzz seed (fuzz/seeds/make_seeds.cpp) and of the FuzzFindings tests: uncompressed,
// observation-only, small embedded gray images.
TEST(RawlogReadIdentity, UncompressedObservationsWithEmbeddedImages)
{
    TempDir dir;
    const std::string path = dir / "small.rawlog";
    {
        mrpt::io::CFileOutputStream out(path);
        auto arch = mrpt::serialization::archiveFrom(out);
        core::StereoRig rig;
        rig.left = rig.right = core::CameraModel::pinhole(16, 12, 10, 10, 8, 6);
        rig.T_left_right = mrpt::poses::CPose3D(0.1, 0, 0, 0, 0, 0);
        for (int k = 0; k < 3; ++k)
        {
            arch << *imuObs(1'000'000'000LL + k * 50'000'000LL - 1'000'000LL, true);
            auto s = stereoObs(rig, 1'000'000'000LL + k * 50'000'000LL);
            cv::Mat img(12, 16, CV_8UC1);
            cv::RNG rng(42 + k);  // not the global RNG: other tests in the process use it
            rng.fill(img, cv::RNG::UNIFORM, 0, 255);
            s->imageLeft = mrpt::img::CImage(img, mrpt::img::DEEP_COPY);
            s->imageRight = mrpt::img::CImage(255 - img, mrpt::img::DEEP_COPY);
            arch << *s;
        }
    }
    expectDigest(path, 3, 3, 0xcc163df43eb5633aULL);
}

// Observation and action classes the reader does not parse are read by MRPT in a child process
// (isolated_object_reader.h): the reader yields the same observations (class, timestamp, order) as MRPT's
// CRawlog::getActionObservationPairOrObservation reading the file in this process, and counts the ignored classes
// in its warnings. gz-compressed, every layout: observations at the top level, action collections (with two
// action classes) followed by sensory frames, a top-level object that is no observation.
TEST(RawlogReadIdentity, OtherClassesAsMrptReadsThem)
{
    using namespace mrpt::obs;
    TempDir dir;
    const std::string path = dir / "other.rawlog";
    core::StereoRig rig;
    rig.left = rig.right = core::CameraModel::pinhole(16, 12, 10, 10, 8, 6);
    rig.T_left_right = mrpt::poses::CPose3D(0.1, 0, 0, 0, 0, 0);
    const std::int64_t t0 = 1'403'715'273'262'142'976LL, ms = 1'000'000;
    {
        mrpt::io::CFileGZOutputStream out(path);
        auto arch = mrpt::serialization::archiveFrom(out);
        auto odometry = CObservationOdometry::Create();
        odometry->timestamp = mrptTimeFromNs(t0 - 20 * ms);
        odometry->odometry = mrpt::poses::CPose2D(1, 2, 0.3);
        auto gps = CObservationGPS::Create();
        gps->timestamp = mrptTimeFromNs(t0 - 10 * ms);
        gnss::Message_NMEA_GGA gga;
        gga.fields.latitude_degrees = 36.8;
        gps->setMsg(gga);
        arch << *odometry << *gps << mrpt::poses::CPose2D(1, 2, 3);

        CActionCollection actions;
        CActionRobotMovement2D move2d;
        move2d.computeFromOdometry(mrpt::poses::CPose2D(0.1, 0, 0.01), {});
        actions.insert(move2d);
        CActionRobotMovement3D move3d;
        move3d.computeFromOdometry(mrpt::poses::CPose3D(0.1, 0, 0, 0.01, 0, 0), {});
        actions.insert(move3d);
        CSensoryFrame frame;
        frame.insert(imuObs(t0 - 2 * ms, true));
        auto s0 = stereoObs(rig, t0);
        s0->imageLeft = s0->imageRight =
            mrpt::img::CImage(cv::Mat(12, 16, CV_8UC1, cv::Scalar(7)), mrpt::img::DEEP_COPY);
        frame.insert(s0);
        auto scan = CObservation2DRangeScan::Create();
        scan->timestamp = mrptTimeFromNs(t0 + 1 * ms);
        scan->resizeScan(181);
        frame.insert(scan);
        auto comment = CObservationComment::Create();
        comment->timestamp = mrptTimeFromNs(t0 + 2 * ms);
        comment->text = "a comment";
        frame.insert(comment);
        odometry->timestamp = mrptTimeFromNs(t0 + 3 * ms);
        frame.insert(odometry);
        arch << actions << frame;

        auto s1 = stereoObs(rig, t0 + 50 * ms);
        s1->imageLeft = s1->imageRight =
            mrpt::img::CImage(cv::Mat(12, 16, CV_8UC1, cv::Scalar(9)), mrpt::img::DEEP_COPY);
        gps->timestamp = mrptTimeFromNs(t0 + 40 * ms);
        arch << *gps << *imuObs(t0 + 45 * ms, true) << *s1;
    }

    // MRPT, in this process: (class, timestamp) of every observation, in order.
    std::vector<std::pair<std::string, std::int64_t>> mrpt_read, ours;
    {
        mrpt::io::CFileGZInputStream in(path);
        auto arch = mrpt::serialization::archiveFrom(in);
        CActionCollection::Ptr acts;
        CSensoryFrame::Ptr sf;
        CObservation::Ptr obs;
        size_t entry = 0;
        while (CRawlog::getActionObservationPairOrObservation(arch, acts, sf, obs, entry))
        {
            if (obs) mrpt_read.emplace_back(obs->GetRuntimeClass()->className, mrptTimeToNs(obs->timestamp));
            if (sf)
                for (const auto& o : *sf)
                    mrpt_read.emplace_back(o->GetRuntimeClass()->className, mrptTimeToNs(o->timestamp));
        }
    }
    detail::RawlogEntries entries(path);
    std::vector<detail::RawlogObservation> read;
    while (entries.next(read))
        for (const auto& o : read) ours.emplace_back(o.class_name, mrptTimeToNs(o.timestamp));
    EXPECT_EQ(ours, mrpt_read);
    ASSERT_EQ(ours.size(), 10u);

    const Digest d = digestOf(path);
    EXPECT_EQ(d.frames, 2u);
    EXPECT_EQ(d.imu_samples, 2u);
    for (const char* warning : {"warning: 1 observations of class mrpt::obs::CObservation2DRangeScan (ignored)",
                                "warning: 1 observations of class mrpt::obs::CObservationComment (ignored)",
                                "warning: 2 observations of class mrpt::obs::CObservationGPS (ignored)",
                                "warning: 2 observations of class mrpt::obs::CObservationOdometry (ignored)"})
        EXPECT_NE(d.text.find(warning), std::string::npos) << warning << " not in:\n" << d.text;
}
