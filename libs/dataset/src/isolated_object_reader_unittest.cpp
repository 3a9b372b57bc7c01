// IsolatedObjectReader (isolated_object_reader.h): MRPT reads the classes the rawlog reader does not parse in a
// child process. What MRPT's readers do on corrupt files (crash, abort, exit, hang) is made deterministic here by an
// observation class of this test, registered with MRPT, whose reading misbehaves as its stored mode byte says.
#include "isolated_object_reader.h"

#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <quasiloc/core/error.h>
#include <quasiloc/dataset/frame_source.h>
#include <quasiloc/dataset/timestamps.h>

#include "rawlog_objects.h"
#include "test_helpers.h"

namespace quasiloc_test
{
constexpr const char* kEscapeFile = "/tmp/quasiloc_isolated_reader_escape_test";

/** An observation whose reading misbehaves as `mode` says (it is read before anything else is done). */
class CObservationMisbehaving : public mrpt::obs::CObservation
{
    DEFINE_SERIALIZABLE(CObservationMisbehaving, quasiloc_test)

   public:
    enum Mode : std::uint8_t
    {
        Fine,
        Segv,
        Abort,
        Exit3,
        Hang,
        Garbage,  ///< writes a report of more bytes than it was sent on the child's socket (fd 3), then waits
        Escape,   ///< tries to create a file, open a network socket, fork and make memory executable; reads a
                  ///< timestamp of 1 ns if any worked
    };
    std::uint8_t mode = Fine;

    void getSensorPose(mrpt::poses::CPose3D&) const override {}
    void setSensorPose(const mrpt::poses::CPose3D&) override {}
};
}  // namespace quasiloc_test

IMPLEMENTS_SERIALIZABLE(CObservationMisbehaving, mrpt::obs::CObservation, quasiloc_test)

namespace quasiloc_test
{
uint8_t CObservationMisbehaving::serializeGetVersion() const { return 0; }
void CObservationMisbehaving::serializeTo(mrpt::serialization::CArchive& out) const { out << mode << timestamp; }
void CObservationMisbehaving::serializeFrom(mrpt::serialization::CArchive& in, uint8_t)
{
    in >> mode;
    if (mode == Segv) std::raise(SIGSEGV);
    if (mode == Abort) std::abort();
    if (mode == Exit3) std::exit(3);
    while (mode == Hang) ::pause();
    if (mode == Escape)
    {
        const int fd = ::open(kEscapeFile, O_CREAT | O_WRONLY, 0600);
        const int sock = ::socket(AF_INET, SOCK_STREAM, 0);
        const pid_t pid = ::fork();
        if (pid == 0) _exit(0);
        // Executable memory, mapped so or re-protected: what injected code needs to run.
        void* exec = ::mmap(nullptr, 4096, PROT_READ | PROT_WRITE | PROT_EXEC, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        void* page = ::mmap(nullptr, 4096, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        const bool reprotected = page != MAP_FAILED && ::mprotect(page, 4096, PROT_READ | PROT_EXEC) == 0;
        in >> timestamp;
        if (fd >= 0 || sock >= 0 || pid > 0 || exec != MAP_FAILED || reprotected)
            timestamp = quasiloc::dataset::mrptTimeFromNs(1);
        return;
    }
    if (mode == Garbage)
    {
        const char done[1 + 4 + 17 + 1] = {'D', 18, 0, 0, 0, 0, 0, 0, 0, 0, 1 /* 2^40 bytes consumed */};
        (void)::send(3, done, sizeof done, MSG_NOSIGNAL);
        for (;;) ::pause();
    }
    in >> timestamp;
}

const bool kRegistered = [] {
    mrpt::rtti::registerClass(CLASS_ID(CObservationMisbehaving));
    return true;
}();
}  // namespace quasiloc_test

using namespace quasiloc;
using namespace quasiloc::dataset;
using namespace quasiloc::dataset::detail;
using quasiloc::dataset::test::TempDir;
using quasiloc_test::CObservationMisbehaving;

namespace
{
/** A rawlog file as the reader's stream sees it. */
struct StreamOf
{
    explicit StreamOf(const std::string& path) { EXPECT_TRUE(file.open(path)); }
    mrpt::io::CFileGZInputStream file;
    RawlogStream stream{file};
};

template <class... Objects>
void writeObjects(const std::string& path, const Objects&... objects)
{
    mrpt::io::CFileOutputStream out(path);
    auto arch = mrpt::serialization::archiveFrom(out);
    (arch << ... << objects);
}

CObservationMisbehaving misbehaving(CObservationMisbehaving::Mode mode)
{
    CObservationMisbehaving o;
    o.mode = mode;
    o.timestamp = mrptTimeFromNs(7'000'000'000);
    return o;
}

mrpt::obs::CObservation2DRangeScan scanOf(size_t beams, std::int64_t t_ns)
{
    mrpt::obs::CObservation2DRangeScan scan;
    scan.resizeScan(beams);
    for (size_t i = 0; i < beams; ++i) scan.setScanRange(i, 1.0f + 0.001f * float(i));
    scan.timestamp = mrptTimeFromNs(t_ns);
    return scan;
}

bool noChildLeft()
{
    errno = 0;
    return ::waitpid(-1, nullptr, WNOHANG) == -1 && errno == ECHILD;
}
}  // namespace

// Objects of several classes one after the other, one larger than a request (64 KiB): one child reads them all,
// and the stream is left after each, so that our own parser reads the next object.
TEST(IsolatedObjectReader, ReadsObjectsOneAfterTheOtherInOneChild)
{
    TempDir dir;
    const std::string path = dir / "objects.rawlog";
    mrpt::obs::CObservationOdometry odometry;
    odometry.timestamp = mrptTimeFromNs(1'000'000'000);
    mrpt::obs::CActionRobotMovement2D move;
    move.computeFromOdometry(mrpt::poses::CPose2D(0.1, 0, 0.01), {});
    mrpt::obs::CObservationIMU imu;
    imu.timestamp = mrptTimeFromNs(3'000'000'000);
    writeObjects(path, odometry, scanOf(40'000, 2'000'000'000), move, imu);

    StreamOf in(path);
    IsolatedObjectReader reader;
    const IsolatedObject a = reader.read(in.stream), b = reader.read(in.stream), c = reader.read(in.stream);
    EXPECT_EQ(a.error + b.error + c.error, "");
    EXPECT_EQ(a.class_name, "mrpt::obs::CObservationOdometry");
    EXPECT_TRUE(a.is_observation);
    EXPECT_EQ(mrptTimeToNs(a.timestamp), 1'000'000'000);
    EXPECT_EQ(b.class_name, "mrpt::obs::CObservation2DRangeScan");
    EXPECT_EQ(mrptTimeToNs(b.timestamp), 2'000'000'000);
    EXPECT_EQ(c.class_name, "mrpt::obs::CActionRobotMovement2D");
    EXPECT_FALSE(c.is_observation);
    EXPECT_EQ(reader.childrenStarted(), 1);

    FieldReader fields(in.stream, path);
    fields.startEntry(3);
    const auto header = readObjectHeader(fields, true);
    ASSERT_TRUE(header && header->id == CLASS_ID(mrpt::obs::CObservationIMU)) << "the stream is not after the action";
    EXPECT_EQ(mrptTimeToNs(parseKnownObject(fields, *header)->timestamp), 3'000'000'000);
    EXPECT_FALSE(readObjectHeader(fields, true)) << "a clean end";
}

// A child that crashes, aborts or calls exit() is an error saying how it ended; the next object gets a new child.
TEST(IsolatedObjectReader, ChildThatCrashesAbortsOrExitsIsAnErrorAndIsReplaced)
{
    TempDir dir;
    const std::string path = dir / "bad.rawlog";
    IsolatedObjectReader reader;
    const std::pair<CObservationMisbehaving::Mode, std::string> cases[] = {
        {CObservationMisbehaving::Segv, "the reading process ended with signal 11 (SIGSEGV)"},
        {CObservationMisbehaving::Abort, "the reading process ended with signal 6 (SIGABRT)"},
        {CObservationMisbehaving::Exit3, "the reading process ended with exit status 3"},
    };
    for (const auto& [mode, expected] : cases)
    {
        writeObjects(path, misbehaving(mode));
        StreamOf in(path);
        const IsolatedObject o = reader.read(in.stream);
        EXPECT_EQ(o.error, expected);
        EXPECT_FALSE(o.truncated);
    }
    writeObjects(path, misbehaving(CObservationMisbehaving::Fine));
    StreamOf in(path);
    const IsolatedObject o = reader.read(in.stream);
    EXPECT_EQ(o.error, "");
    EXPECT_EQ(o.class_name, "quasiloc_test::CObservationMisbehaving");
    EXPECT_EQ(mrptTimeToNs(o.timestamp), 7'000'000'000);
    EXPECT_EQ(reader.childrenStarted(), 4);
}

// The child's system-call filter: MRPT's reading may compute, allocate and use its socket, nothing else. A reader
// that tries to create a file, open a network socket or fork is refused (EPERM) and its object still reads.
TEST(IsolatedObjectReader, ChildCannotCreateFilesOpenSocketsForkOrMakeMemoryExecutable)
{
    TempDir dir;
    const std::string path = dir / "escape.rawlog";
    std::filesystem::remove(quasiloc_test::kEscapeFile);
    writeObjects(path, misbehaving(CObservationMisbehaving::Escape));
    StreamOf in(path);
    IsolatedObjectReader reader;
    const IsolatedObject o = reader.read(in.stream);
    EXPECT_EQ(o.error, "");
    EXPECT_EQ(mrptTimeToNs(o.timestamp), 7'000'000'000) << "a file, a socket, a process or executable memory was made";
    EXPECT_FALSE(std::filesystem::exists(quasiloc_test::kEscapeFile));
    std::filesystem::remove(quasiloc_test::kEscapeFile);
}

TEST(IsolatedObjectReader, ChildThatHangsIsKilledAtTheTimeout)
{
    TempDir dir;
    const std::string path = dir / "hang.rawlog";
    writeObjects(path, misbehaving(CObservationMisbehaving::Hang));
    StreamOf in(path);
    IsolatedObjectReader::Options options;
    options.timeout_ms = 300;
    IsolatedObjectReader reader(options);
    const auto start = std::chrono::steady_clock::now();
    EXPECT_EQ(reader.read(in.stream).error, "the reading process did not answer within 300 ms (killed)");
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
}

TEST(IsolatedObjectReader, ChildThatBreaksTheProtocolIsKilled)
{
    TempDir dir;
    const std::string path = dir / "garbage.rawlog";
    writeObjects(path, misbehaving(CObservationMisbehaving::Garbage));
    StreamOf in(path);
    IsolatedObjectReader reader;
    const std::string error = reader.read(in.stream).error;
    EXPECT_NE(error.find("the reading process broke the protocol (1099511627776 bytes consumed of"), std::string::npos)
        << error;
}

// The child's address space may grow by the budget only: a std::string of 256 MiB (a comment's length field) is
// std::bad_alloc there with a budget of 32 MiB.
TEST(IsolatedObjectReader, AllocationBeyondTheMemoryBudgetIsAnError)
{
    TempDir dir;
    const std::string path = dir / "big.rawlog";
    mrpt::obs::CObservationComment comment;
    comment.text = "a comment";
    writeObjects(path, comment);
    std::string bytes;
    {
        std::ifstream f(path, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
    }
    const size_t at = bytes.find(comment.text);
    ASSERT_NE(at, std::string::npos);
    ASSERT_EQ(bytes[at - 4], char(comment.text.size())) << "MRPT's CObservationComment layout changed";
    bytes[at - 1] = 0x10;  // + 256 MiB
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;

    StreamOf in(path);
    IsolatedObjectReader::Options options;
    options.memory_budget_bytes = 32ULL << 20;
    IsolatedObjectReader reader(options);
    EXPECT_EQ(reader.read(in.stream).error,
              "it needs more memory than the 32 MiB the reading process may add (a length field of the file, "
              "corrupt?)");
}

TEST(IsolatedObjectReader, ObjectCutByTheEndOfTheFileIsTruncated)
{
    TempDir dir;
    const std::string path = dir / "cut.rawlog";
    writeObjects(path, scanOf(100, 0));
    std::filesystem::resize_file(path, std::filesystem::file_size(path) - 50);
    StreamOf in(path);
    IsolatedObjectReader reader;
    const IsolatedObject o = reader.read(in.stream);
    EXPECT_NE(o.error, "");
    EXPECT_TRUE(o.truncated);
}

TEST(IsolatedObjectReader, LeavesNoChildBehind)
{
    TempDir dir;
    const std::string path = dir / "objects.rawlog";
    writeObjects(path, scanOf(10, 0), misbehaving(CObservationMisbehaving::Segv));
    {
        StreamOf in(path);
        IsolatedObjectReader reader;
        EXPECT_EQ(reader.read(in.stream).error, "");
        EXPECT_FALSE(noChildLeft()) << "the child is kept for the next object";
        EXPECT_NE(reader.read(in.stream).error, "");
        EXPECT_TRUE(noChildLeft()) << "the crashed child is reaped";
        // A new child; the stream is at its end now (the crashed child had been sent the rest): MRPT's error.
        EXPECT_EQ(reader.read(in.stream).error.find("the reading process"), std::string::npos);
    }
    EXPECT_TRUE(noChildLeft()) << "the reader reaps its child";
}

namespace
{
mrpt::obs::CObservationStereoImages::Ptr smallStereo()
{
    auto stereo = mrpt::obs::CObservationStereoImages::Create();
    stereo->timestamp = mrptTimeFromNs(1'000'000'000);
    stereo->leftCamera = stereo->rightCamera = core::CameraModel::pinhole(16, 12, 10, 10, 8, 6).toTCamera();
    stereo->rightCameraPose = mrpt::poses::CPose3DQuat(mrpt::poses::CPose3D(0.1, 0, 0, 0, 0, 0));
    stereo->hasImageRight = true;
    const cv::Mat img(12, 16, CV_8UC1, cv::Scalar(50));
    stereo->imageLeft = stereo->imageRight = mrpt::img::CImage(img, mrpt::img::DEEP_COPY);
    return stereo;
}

/** Reads every frame of `path`; the InputError's message, or "" when there is none. */
std::string rawlogError(const std::string& path, const FrameSourceOptions& options = {})
{
    try
    {
        auto source = openRawlog(path, options);
        StereoFrame f;
        while (source->next(f))
        {}
        return "";
    }
    catch (const core::InputError& e)
    {
        std::cout << "  expected InputError: " << e.what() << std::endl;
        return e.what();
    }
}
}  // namespace

// Through openRawlog: the error names the file, the entry, where the object starts and its class.
TEST(IsolatedObjectReader, CrashInsideASensoryFrameIsAnInputErrorNamingFileEntryAndClass)
{
    TempDir dir;
    const std::string path = dir / "crash.rawlog";
    mrpt::obs::CSensoryFrame frame;
    auto odometry = mrpt::obs::CObservationOdometry::Create();
    odometry->timestamp = mrptTimeFromNs(2'000'000'000);
    frame.insert(odometry);
    frame.insert(std::make_shared<CObservationMisbehaving>(misbehaving(CObservationMisbehaving::Segv)));
    writeObjects(path, *smallStereo(), mrpt::obs::CActionCollection(), frame);
    const std::string what = rawlogError(path);
    for (const char* needle :
         {"crash.rawlog: entry 2 (at byte", "mrpt::obs::CSensoryFrame > observation 1",
          "MRPT could not read the object of class quasiloc_test::CObservationMisbehaving (at byte",
          "the reading process ended with signal 11 (SIGSEGV)"})
        EXPECT_NE(what.find(needle), std::string::npos) << "'" << needle << "' not in: " << what;
}

// openRawlog passes FrameSourceOptions::mrpt_object_timeout_s to the child's reader.
TEST(IsolatedObjectReader, ObjectThatHangsIsAnInputErrorAfterTheTimeoutOfTheOptions)
{
    TempDir dir;
    const std::string path = dir / "hang.rawlog";
    writeObjects(path, *smallStereo(), misbehaving(CObservationMisbehaving::Hang));
    FrameSourceOptions options;
    options.mrpt_object_timeout_s = 0.2;
    const std::string what = rawlogError(path, options);
    EXPECT_NE(what.find("entry 1 (at byte"), std::string::npos) << what;
    EXPECT_NE(what.find("the reading process did not answer within 200 ms (killed)"), std::string::npos) << what;
}
