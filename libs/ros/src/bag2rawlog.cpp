// convertBagToRawlog (bag2rawlog.h): the bag (any MessageSource: ROS 1, rosbag2 SQLite3 or MCAP) is streamed in time
// order; left and right images are paired by their header stamps (dataset::StereoPairer); pairs and IMU samples wait
// in a short reorder buffer so that the rawlog is written in time order even when one topic is recorded late.
#include <mrpt/core/format.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/dataset/calibration.h>
#include <quasiloc/dataset/rawlog_writer.h>
#include <quasiloc/dataset/stereo_pairing.h>
#include <quasiloc/dataset/timestamps.h>
#include <quasiloc/ros/bag2rawlog.h>
#include <quasiloc/ros/bag_images.h>
#include <quasiloc/ros/message_source.h>
#include <unordered_map>

#include "bag2rawlog_calibration.h"

namespace fs = std::filesystem;
using quasiloc::core::InputError;
using quasiloc::core::require;

namespace quasiloc::ros
{
namespace
{
const char* kSection = "Bag2Rawlog";

std::string key(const std::string& k) { return std::string("[") + kSection + "] " + k; }

/** One observation waiting in the reorder buffer. */
struct Pending
{
    bool stereo = false;
    cv::Mat left, right;
    dataset::ImuSample imu;
};

class Converter
{
   public:
    Converter(const Bag2RawlogOptions& o, mrpt::system::CTimeLogger* timer) : o_(o), timer_(timer) {}
    Bag2RawlogResult run();

   private:
    std::string requireTopic(const std::string& key_name, const std::string& topic,
                             const std::vector<std::string>& types) const;
    void readAll(dataset::RawlogWriter& writer);
    void handle(const BagMessage& m);
    void handleImage(const BagMessage& m, bool left);
    void handleGroundTruth(const BagMessage& m);
    void takePairs();
    void flush(std::int64_t horizon_ns);
    void progress(std::int64_t t_ns, bool done);
    static std::int64_t stampNs(const MsgHeader& header, const BagMessage& m)
    {
        return header.stamp_ns == 0 ? m.timeNs() : header.stamp_ns;
    }

    const Bag2RawlogOptions& o_;
    mrpt::system::CTimeLogger* timer_;
    dataset::SensorCalibration calib_;
    std::unique_ptr<MessageSource> bag_;
    Bag2RawlogResult r_;
    dataset::RawlogWriter* writer_ = nullptr;
    std::unique_ptr<dataset::StereoPairer> pairer_;
    std::unordered_map<std::size_t, cv::Mat> images_;
    std::size_t next_id_ = 0;
    /** Keyed by (time, 0 for IMU / 1 for stereo): an IMU sample stamped with a frame's time goes first, as
     *  euroc2rawlog and the simulator write them, whatever order the bag's index gives messages of equal time. */
    std::multimap<std::pair<std::int64_t, int>, Pending> buffer_;
    std::int64_t newest_ns_ = std::numeric_limits<std::int64_t>::min();
    std::int64_t last_written_ns_ = std::numeric_limits<std::int64_t>::min();
    core::Trajectory gt_;
    std::pair<std::int64_t, std::int64_t> span_{0, 0};
    int shown_percent_ = -1;
    bool enough_frames_ = false;
};

std::string Converter::requireTopic(const std::string& key_name, const std::string& topic,
                                    const std::vector<std::string>& types) const
{
    const auto& topic_types = bag_->topicTypes();
    const auto it = topic_types.find(topic);
    if (it == topic_types.end())
    {
        std::string present;
        for (const auto& [name, type] : topic_types) present += "\n  " + name + " (" + type + ")";
        throw InputError(o_.input_bag + " topic " + topic + " (" + key(key_name) + ")",
                         "not in the bag; its topics are:" + (present.empty() ? std::string(" none") : present));
    }
    std::string allowed;
    for (const auto& t : types)
    {
        if (it->second == t) return t;
        allowed += (allowed.empty() ? "" : ", ") + t;
    }
    throw InputError(o_.input_bag + " topic " + topic + " (" + key(key_name) + ")",
                     "holds " + it->second + ", expected " + allowed);
}

void Converter::handleImage(const BagMessage& m, bool left)
{
    cv::Mat gray;
    std::int64_t t_ns = 0;
    if (m.type() == types::kImage)
    {
        const ImageMsg msg = m.image();
        t_ns = stampNs(msg.header, m);
        gray = grayFromImageMsg(msg, o_.mono16_shift_bits, m.where());
    }
    else
    {
        const CompressedImageMsg msg = m.compressedImage();
        t_ns = stampNs(msg.header, m);
        gray = grayFromCompressedMsg(msg, m.where());
    }
    const core::CameraModel& cam = left ? calib_.rig.left : calib_.rig.right;
    require(gray.cols == cam.width && gray.rows == cam.height, m.where(),
            "image is " + std::to_string(gray.cols) + "x" + std::to_string(gray.rows) + ", the calibration's " +
                (left ? "left" : "right") + " camera is " + std::to_string(cam.width) + "x" +
                std::to_string(cam.height));
    ++(left ? r_.left_msgs : r_.right_msgs);
    const std::size_t id = next_id_++;
    images_.emplace(id, std::move(gray));
    if (left)
        pairer_->addLeft(t_ns, id);
    else
        pairer_->addRight(t_ns, id);
    takePairs();
}

void Converter::takePairs()
{
    for (const auto& p : pairer_->takePairs())
    {
        Pending item;
        item.stereo = true;
        item.left = std::move(images_.at(p.left_id));
        item.right = std::move(images_.at(p.right_id));
        images_.erase(p.left_id);
        images_.erase(p.right_id);
        r_.max_pair_offset_ms = std::max(r_.max_pair_offset_ms, std::abs(double(p.right_ns - p.left_ns)) * 1e-6);
        newest_ns_ = std::max(newest_ns_, p.left_ns);
        buffer_.emplace(std::make_pair(p.left_ns, 1), std::move(item));
    }
    for (const auto& u : pairer_->takeUnpaired())
    {
        images_.erase(u.id);
        if (u.out_of_order) ++r_.out_of_order;
        if (r_.unpaired_report.size() < 5)
            r_.unpaired_report.push_back(
                std::string(u.left ? "left image on " + o_.left_topic : "right image on " + o_.right_topic) +
                " at t=" + std::to_string(u.t_ns) + " ns" +
                (u.out_of_order ? ": not later than the previous image of its topic"
                                : ": no image of the other camera within the tolerance"));
    }
}

void Converter::handleGroundTruth(const BagMessage& m)
{
    const PoseMsg msg = m.pose();
    const std::int64_t t_ns = stampNs(msg.header, m);
    const Eigen::Vector3d& t = msg.position;
    const Eigen::Quaterniond& q = msg.orientation;
    ++r_.gt_msgs;
    require(t.allFinite() && std::abs(q.norm() - 1.0) < 1e-3, m.where(),
            "pose with a non-finite value or a non-unit quaternion");
    mrpt::poses::CPose3D T_world_x = core::fromTranslationQuaternion(t, q.normalized());
    const auto T_world_cam0 =
        o_.groundtruth_frame == GroundTruthFrame::Body ? T_world_x + calib_.rig.T_body_left : T_world_x;
    if (!gt_.poses.empty() && dataset::secondsToNs(gt_.poses.back().t) >= t_ns) return;  // repeated or late: drop
    gt_.poses.push_back({dataset::nsToSeconds(t_ns), T_world_cam0});
}

void Converter::handle(const BagMessage& m)
{
    const std::string& topic = m.topic();
    if (topic == o_.left_topic) handleImage(m, true);
    if (topic == o_.right_topic) handleImage(m, false);
    if (topic == o_.imu_topic)
    {
        const ImuMsg msg = m.imu();
        const std::int64_t t_ns = stampNs(msg.header, m);
        Pending item;
        item.imu.t = dataset::nsToSeconds(t_ns);
        item.imu.acc = msg.linear_acceleration;
        item.imu.gyro = msg.angular_velocity;
        require(item.imu.acc.allFinite() && item.imu.gyro.allFinite(), m.where(), "non-finite IMU value");
        ++r_.imu_msgs;
        newest_ns_ = std::max(newest_ns_, t_ns);
        buffer_.emplace(std::make_pair(t_ns, 0), std::move(item));
    }
    if (!o_.groundtruth_topic.empty() && topic == o_.groundtruth_topic) handleGroundTruth(m);
    flush(newest_ns_ - std::int64_t(o_.reorder_window_s * 1e9));
}

void Converter::flush(std::int64_t horizon_ns)
{
    while (!buffer_.empty() && buffer_.begin()->first.first <= horizon_ns)
    {
        const auto node = buffer_.extract(buffer_.begin());
        const std::int64_t t_ns = node.key().first;
        const Pending& item = node.mapped();
        const bool frames_done = o_.max_frames > 0 && r_.stereo_written >= std::size_t(o_.max_frames);
        if (t_ns < last_written_ns_)
            ++r_.late_dropped;  // arrived later than the reorder window allows
        else if (item.stereo && !frames_done)
        {
            writer_->writeStereoNs(t_ns, item.left, item.right);
            if (r_.stereo_written == 0) r_.first_frame_ns = t_ns;
            r_.last_frame_ns = t_ns;
            ++r_.stereo_written;
            last_written_ns_ = t_ns;
        }
        else if (!item.stereo && !frames_done)
        {
            writer_->writeImuNs(t_ns, item.imu);
            ++r_.imu_written;
            last_written_ns_ = t_ns;
        }
    }
    if (o_.max_frames > 0 && r_.stereo_written >= std::size_t(o_.max_frames)) enough_frames_ = true;
}

void Converter::progress(std::int64_t t_ns, bool done)
{
    if (!o_.progress) return;
    const bool tty = isatty(STDERR_FILENO);
    const double span = double(span_.second - span_.first);
    const double f = done ? 1.0 : span > 0 ? double(t_ns - span_.first) / span : 0.0;
    const int percent = std::clamp(int(f * 100), 0, 100);
    if (percent == shown_percent_ || (!tty && percent % 10 != 0 && !done)) return;
    shown_percent_ = percent;
    const int width = 40, filled = percent * width / 100;
    std::fprintf(stderr, "%s[%s%s] %3d%%  %zu stereo frames, %zu IMU samples%s", tty ? "\r" : "",
                 std::string(filled, '#').c_str(), std::string(width - filled, '.').c_str(), percent, r_.stereo_written,
                 r_.imu_written, tty && !done ? "" : "\n");
    std::fflush(stderr);
}

void Converter::readAll(dataset::RawlogWriter& writer)
{
    writer_ = &writer;
    std::vector<std::string> topics = {o_.left_topic, o_.right_topic, o_.imu_topic};
    if (!o_.groundtruth_topic.empty()) topics.push_back(o_.groundtruth_topic);
    pairer_ = std::make_unique<dataset::StereoPairer>(std::int64_t(std::llround(o_.pair_tolerance_ms * 1e6)));
    span_ = bag_->timeSpanNs();
    bag_->read(topics, [&](const BagMessage& m) {
        handle(m);
        progress(m.timeNs(), false);
        return !enough_frames_;
    });
    pairer_->finish();
    takePairs();
    flush(std::numeric_limits<std::int64_t>::max());
    r_.unpaired_left = pairer_->numUnpairedLeft();
    r_.unpaired_right = pairer_->numUnpairedRight();
}

Bag2RawlogResult Converter::run()
{
    bag_ = openMessageSource(o_.input_bag);
    r_.bag_bytes = bag_->bytes();
    r_.bag_format = bag_->describe();
    r_.left_type = requireTopic("left_topic", o_.left_topic, {types::kImage, types::kCompressedImage});
    r_.right_type = requireTopic("right_topic", o_.right_topic, {types::kImage, types::kCompressedImage});
    requireTopic("imu_topic", o_.imu_topic, {types::kImu});
    if (!o_.groundtruth_topic.empty())
        requireTopic("groundtruth_topic", o_.groundtruth_topic,
                     {types::kPoseStamped, types::kTransformStamped, types::kOdometry});
    const Bag2RawlogCalibration calibration = bag2rawlogCalibration(o_, *bag_);
    calib_ = calibration.calib;

    dataset::RawlogWriter::Options wo;
    wo.stereo_sensor_label = o_.stereo_sensor_label;
    wo.imu_sensor_label = o_.imu_sensor_label;
    wo.gz_compression_level = o_.gz_compression_level;
    dataset::RawlogWriter writer(o_.output, calib_.rig, wo);
    core::StagedOutputs staged;
    const std::string calib_tmp = staged.addFile(o_.calibOutPath());
    if (timer_) timer_->enter("read bag, write rawlog");
    readAll(writer);
    if (timer_) timer_->leave("read bag, write rawlog");
    require(r_.stereo_written > 0, o_.input_bag + " topics " + o_.left_topic + " and " + o_.right_topic,
            "no stereo pair: " + std::to_string(r_.left_msgs) + " left and " + std::to_string(r_.right_msgs) +
                " right images, none within " + mrpt::format("%g", o_.pair_tolerance_ms) + " ms of each other (" +
                key("pair_tolerance_ms") + ")");
    require(r_.imu_written > 0, o_.input_bag + " topic " + o_.imu_topic, "no IMU message");
    dataset::saveCalibration(calib_, calib_tmp,
                             "calibration written by bag2rawlog from " + calibration.sources +
                                 "; the biases were not measured (zero, with the sigmas of real MEMS biases)");
    if (!o_.groundtruth_topic.empty())
    {
        require(!gt_.poses.empty(), o_.input_bag + " topic " + o_.groundtruth_topic, "no ground-truth message");
        gt_.header =
            "T_world_cam0 from " + o_.input_bag + " topic " + o_.groundtruth_topic + "\nt tx ty tz qx qy qz qw";
        core::writeTum(staged.addFile(o_.gtOutPath()), gt_);
        r_.gt_path = o_.gtOutPath();
        r_.gt_written = gt_.poses.size();
    }
    writer.close();
    staged.commit();
    r_.rawlog_path = writer.rawlogPath();
    r_.images_folder = writer.imagesFolder();
    r_.calib_path = o_.calibOutPath();
    return r_;
}
}  // namespace

Bag2RawlogResult convertBagToRawlog(const Bag2RawlogOptions& options, mrpt::system::CTimeLogger* timer)
{
    options.check();
    return Converter(options, timer).run();
}

}  // namespace quasiloc::ros
