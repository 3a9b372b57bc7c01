#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/poses/CPose3DQuat.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/dataset/rawlog_writer.h>
#include <quasiloc/dataset/timestamps.h>

#include "image_checks.h"

namespace fs = std::filesystem;
using quasiloc::core::require;

namespace quasiloc::dataset
{
std::string rawlogImagesFolder(const std::string& rawlog_path)
{
    const fs::path p(rawlog_path);
    return (p.parent_path() / (p.stem().string() + "_Images")).string();
}

struct RawlogWriter::Impl
{
    // Declared before `out` so that the stream is closed before the staged files are removed.
    core::StagedOutputs staged;
    std::string rawlog_path, images_folder, tmp_rawlog, tmp_images;
    core::StereoRig rig;
    Options options;
    mrpt::io::CFileGZOutputStream out;
    bool closed = false;

    void writeObservation(const mrpt::serialization::CSerializable& obs)
    {
        require(!closed, rawlog_path, "RawlogWriter: write after close()");
        auto arch = mrpt::serialization::archiveFrom(out);
        arch << obs;
    }

    /** File name (relative to the images folder) of one image of a stereo pair. */
    std::string imageName(std::int64_t t_ns, const char* side) const
    {
        return options.stereo_sensor_label + "_" + std::to_string(t_ns) + "_" + side + ".png";
    }

    void writeImageBytes(const std::string& name, const std::vector<unsigned char>& bytes) const
    {
        const fs::path path = fs::path(tmp_images) / name;
        require(!fs::exists(path), rawlog_path, "two stereo observations with the same timestamp (" + name + ")");
        std::ofstream f(path, std::ios::binary);
        f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
        f.close();
        require(!f.fail(), path.string(), "cannot write image file");
    }

    void writeStereoObservation(std::int64_t t_ns, const std::string& left_name, const std::string& right_name)
    {
        mrpt::obs::CObservationStereoImages obs;
        obs.sensorLabel = options.stereo_sensor_label;
        obs.timestamp = mrptTimeFromNs(t_ns);
        obs.leftCamera = rig.left.toTCamera();
        obs.rightCamera = rig.right.toTCamera();
        obs.rightCameraPose = mrpt::poses::CPose3DQuat(rig.T_left_right);
        obs.cameraPose = mrpt::poses::CPose3DQuat(rig.T_body_left);
        obs.hasImageRight = true;
        obs.hasImageDisparity = false;
        obs.imageLeft.setExternalStorage(left_name);
        obs.imageRight.setExternalStorage(right_name);
        writeObservation(obs);
    }
};

RawlogWriter::RawlogWriter(const std::string& rawlog_path, const core::StereoRig& rig)
    : RawlogWriter(rawlog_path, rig, Options())
{}

RawlogWriter::RawlogWriter(const std::string& rawlog_path, const core::StereoRig& rig, const Options& options)
    : impl_(std::make_unique<Impl>())
{
    require(!rawlog_path.empty(), "rawlog path", "is empty");
    require(!options.stereo_sensor_label.empty() && !options.imu_sensor_label.empty(), rawlog_path,
            "RawlogWriter: sensor labels must not be empty");
    require(options.gz_compression_level >= 0 && options.gz_compression_level <= 9, rawlog_path,
            "RawlogWriter: gz_compression_level must be 0..9");
    rig.check("stereo rig of " + rawlog_path);
    Impl& m = *impl_;
    m.rawlog_path = rawlog_path;
    m.images_folder = rawlogImagesFolder(rawlog_path);
    m.rig = rig;
    m.options = options;
    m.tmp_rawlog = m.staged.addFile(rawlog_path);
    m.tmp_images = m.staged.addFolder(m.images_folder);
    require(m.out.open(m.tmp_rawlog, options.gz_compression_level), rawlog_path, "cannot open for writing");
}

RawlogWriter::~RawlogWriter()
{
    // Without close(), Impl's StagedOutputs removes the temporary rawlog and images folder.
    if (impl_ && !impl_->closed && impl_->out.fileOpenCorrectly()) impl_->out.close();
}

void RawlogWriter::writeStereo(double timestamp, const cv::Mat& left, const cv::Mat& right)
{
    require(std::isfinite(timestamp), impl_->rawlog_path, "stereo timestamp is not finite");
    writeStereoNs(secondsToNs(timestamp), left, right);
}

void RawlogWriter::writeStereoNs(std::int64_t timestamp_ns, const cv::Mat& left, const cv::Mat& right)
{
    Impl& m = *impl_;
    require(!m.closed, m.rawlog_path, "RawlogWriter: write after close()");
    const std::string what = m.rawlog_path + " (stereo image at t_ns=" + std::to_string(timestamp_ns) + ")";
    detail::requireGrayOfCameraSize(left, m.rig.left, what + " left", "left");
    detail::requireGrayOfCameraSize(right, m.rig.right, what + " right", "right");
    const std::string left_name = m.imageName(timestamp_ns, "left");
    const std::string right_name = m.imageName(timestamp_ns, "right");
    std::vector<unsigned char> bytes;
    require(cv::imencode(".png", left, bytes), what, "PNG encoding failed");
    m.writeImageBytes(left_name, bytes);
    require(cv::imencode(".png", right, bytes), what, "PNG encoding failed");
    m.writeImageBytes(right_name, bytes);
    m.writeStereoObservation(timestamp_ns, left_name, right_name);
    ++num_stereo_;
}

void RawlogWriter::writeStereoFromPngFiles(double timestamp, const std::string& left_png, const std::string& right_png)
{
    require(std::isfinite(timestamp), impl_->rawlog_path, "stereo timestamp is not finite");
    writeStereoFromPngFilesNs(secondsToNs(timestamp), left_png, right_png);
}

namespace
{
/** The file's bytes after checking it is a PNG that decodes to 8-bit gray of the camera's size. */
std::vector<unsigned char> readCheckedPng(const std::string& path, const core::CameraModel& cam,
                                          const std::string& camera_name)
{
    std::vector<unsigned char> bytes = detail::readFileBytes(path);
    static const unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    require(bytes.size() > 8 && std::equal(kPngSignature, kPngSignature + 8, bytes.begin()), path, "not a PNG file");
    // Decoding costs a few ms per image but catches truncated or corrupt files before they are copied.
    const cv::Mat img = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
    require(!img.empty(), path, "cannot decode the PNG file");
    detail::requireGrayOfCameraSize(img, cam, path, camera_name);
    return bytes;
}
}  // namespace

void RawlogWriter::writeStereoFromPngFilesNs(std::int64_t timestamp_ns, const std::string& left_png,
                                             const std::string& right_png)
{
    Impl& m = *impl_;
    require(!m.closed, m.rawlog_path, "RawlogWriter: write after close()");
    const auto left_bytes = readCheckedPng(left_png, m.rig.left, "left");
    const auto right_bytes = readCheckedPng(right_png, m.rig.right, "right");
    const std::string left_name = m.imageName(timestamp_ns, "left");
    const std::string right_name = m.imageName(timestamp_ns, "right");
    m.writeImageBytes(left_name, left_bytes);
    m.writeImageBytes(right_name, right_bytes);
    m.writeStereoObservation(timestamp_ns, left_name, right_name);
    ++num_stereo_;
}

void RawlogWriter::writeImu(const ImuSample& sample)
{
    require(std::isfinite(sample.t), impl_->rawlog_path, "IMU timestamp is not finite");
    writeImuNs(secondsToNs(sample.t), sample);
}

void RawlogWriter::writeImuNs(std::int64_t timestamp_ns, const ImuSample& sample)
{
    using namespace mrpt::obs;
    Impl& m = *impl_;
    require(sample.acc.allFinite() && sample.gyro.allFinite(), m.rawlog_path,
            "IMU sample at t_ns=" + std::to_string(timestamp_ns) + " has a non-finite value");
    CObservationIMU obs;
    obs.sensorLabel = m.options.imu_sensor_label;
    obs.timestamp = mrptTimeFromNs(timestamp_ns);
    obs.sensorPose = mrpt::poses::CPose3D();  // body frame = IMU frame
    obs.dataIsPresent.fill(false);
    obs.rawMeasurements.fill(0.0);
    obs.set(IMU_X_ACC, sample.acc.x());
    obs.set(IMU_Y_ACC, sample.acc.y());
    obs.set(IMU_Z_ACC, sample.acc.z());
    obs.set(IMU_WX, sample.gyro.x());
    obs.set(IMU_WY, sample.gyro.y());
    obs.set(IMU_WZ, sample.gyro.z());
    m.writeObservation(obs);
    ++num_imu_;
}

void RawlogWriter::close()
{
    Impl& m = *impl_;
    require(!m.closed, m.rawlog_path, "RawlogWriter: close() called twice");
    m.out.close();
    m.closed = true;
    m.staged.commit();
}

const std::string& RawlogWriter::rawlogPath() const { return impl_->rawlog_path; }
const std::string& RawlogWriter::imagesFolder() const { return impl_->images_folder; }

}  // namespace quasiloc::dataset
