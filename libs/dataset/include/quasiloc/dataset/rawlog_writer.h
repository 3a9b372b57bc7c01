#pragma once
// RawlogWriter: writes stereo frames and IMU samples as an MRPT rawlog (observations-only format) with
// the images stored externally as PNG in `<name>_Images/` beside the rawlog, as MRPT tools expect.
// Used by euroc2rawlog and by the simulator. Output is staged: nothing appears at the final paths
// until close() succeeds.
#include <cstdint>
#include <memory>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/dataset/frame.h>
#include <string>

namespace quasiloc::dataset
{
class RawlogWriter
{
   public:
    struct Options
    {
        std::string stereo_sensor_label = "stereo";  ///< CObservationStereoImages::sensorLabel
        std::string imu_sensor_label = "imu";
        int gz_compression_level = 1;  ///< 0..9; the images are PNG files, so only the observations are gzipped
    };
    /** Starts writing `rawlog_path` (e.g. out/seq.rawlog, images into out/seq_Images/). */
    RawlogWriter(const std::string& rawlog_path, const core::StereoRig& rig, const Options& options);
    RawlogWriter(const std::string& rawlog_path, const core::StereoRig& rig);
    ~RawlogWriter();  ///< without close(): removes everything written

    /** Writes a stereo observation; images are CV_8UC1 of the rig's size, stored as PNG (lossless). */
    void writeStereo(double timestamp, const cv::Mat& left, const cv::Mat& right);
    /** Copies already-encoded PNG files byte for byte (no re-encoding) as the stereo pair's images. */
    void writeStereoFromPngFiles(double timestamp, const std::string& left_png, const std::string& right_png);
    void writeImu(const ImuSample& sample);

    /** The same with the timestamp as integer nanoseconds (exact image file names and MRPT timestamps, e.g.
     *  for EuRoC, whose timestamps do not survive a round trip through double seconds). */
    void writeStereoFromPngFilesNs(std::int64_t timestamp_ns, const std::string& left_png,
                                   const std::string& right_png);
    void writeStereoNs(std::int64_t timestamp_ns, const cv::Mat& left, const cv::Mat& right);
    void writeImuNs(std::int64_t timestamp_ns, const ImuSample& sample);

    /** Flushes, then moves the rawlog and its image folder into place. */
    void close();

    size_t numStereo() const { return num_stereo_; }
    size_t numImu() const { return num_imu_; }
    const std::string& rawlogPath() const;    ///< the final path given to the constructor
    const std::string& imagesFolder() const;  ///< the final `<name>_Images` folder

   private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    size_t num_stereo_ = 0, num_imu_ = 0;
};

/** `<dir>/<name>_Images` for `<dir>/<name>.<ext>`: where MRPT tools look for a rawlog's external images. */
std::string rawlogImagesFolder(const std::string& rawlog_path);

}  // namespace quasiloc::dataset
