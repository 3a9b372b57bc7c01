// The calibration of bag2rawlog (bag2rawlog_calibration.h).
#include "bag2rawlog_calibration.h"

#include <optional>
#include <quasiloc/core/error.h>
#include <quasiloc/dataset/kalibr.h>
#include <quasiloc/ros/bag_calibration.h>

using quasiloc::core::InputError;
using quasiloc::core::require;

namespace quasiloc::ros
{
namespace
{
std::string key(const std::string& k) { return "[Bag2Rawlog] " + k; }

void requireTopicOfType(const MessageSource& bag, const std::string& topic, const std::string& key_name,
                        const char* type)
{
    const auto& types = bag.topicTypes();
    const auto it = types.find(topic);
    require(it != types.end(), bag.path() + " topic " + topic + " (" + key(key_name) + ")",
            "not in the bag, and no kalibr_camchain was given: the cameras' calibration comes from their "
            "CameraInfo");
    require(it->second == type, bag.path() + " topic " + topic + " (" + key(key_name) + ")",
            "holds " + it->second + ", expected " + type);
}

core::StereoRig rigFromBag(const dataset::Bag2RawlogOptions& o, MessageSource& bag, std::string& sources)
{
    const std::string left_topic = o.leftCameraInfoTopic(), right_topic = o.rightCameraInfoTopic();
    requireTopicOfType(bag, left_topic, "left_camera_info_topic", types::kCameraInfo);
    requireTopicOfType(bag, right_topic, "right_camera_info_topic", types::kCameraInfo);
    requireTopicOfType(bag, o.tf_static_topic, "tf_static_topic", types::kTFMessage);
    BagCalibrationInput in;
    in.left_where = bag.path() + " topic " + left_topic;
    in.right_where = bag.path() + " topic " + right_topic;
    in.tf_where = bag.path() + " topic " + o.tf_static_topic;
    in.imu_frame = o.imu_frame;
    bool have_left = false, have_right = false;
    const auto linked = [&] {
        return have_left && have_right && !in.imu_frame.empty() &&
               in.tf.lookup(in.imu_frame, in.left.header.frame_id) &&
               in.tf.lookup(in.left.header.frame_id, in.right.header.frame_id);
    };
    bag.read({left_topic, right_topic, o.tf_static_topic, o.imu_topic}, [&](const BagMessage& m) {
        if (m.topic() == left_topic && !have_left)
        {
            in.left = m.cameraInfo();
            have_left = true;
        }
        else if (m.topic() == right_topic && !have_right)
        {
            in.right = m.cameraInfo();
            have_right = true;
        }
        else if (m.topic() == o.tf_static_topic)
            for (const auto& t : m.transforms()) in.tf.add(t);
        else if (m.topic() == o.imu_topic && in.imu_frame.empty())
        {
            in.imu_frame = m.imu().header.frame_id;
            require(!in.imu_frame.empty(), m.where(), "IMU message without a frame_id: give [Bag2Rawlog] imu_frame");
        }
        return !linked();
    });
    require(have_left, in.left_where, "no CameraInfo message");
    require(have_right, in.right_where, "no CameraInfo message");
    require(!in.imu_frame.empty(), bag.path() + " topic " + o.imu_topic, "no IMU message, so no IMU frame");
    sources = bag.path() + " (" + left_topic + ", " + right_topic + ", " + o.tf_static_topic + ", IMU frame '" +
              in.imu_frame + "')";
    return stereoRigFromBag(in);
}
}  // namespace

Bag2RawlogCalibration bag2rawlogCalibration(const dataset::Bag2RawlogOptions& o, MessageSource& bag)
{
    Bag2RawlogCalibration r;
    if (!o.calibration_ini.empty())
    {
        r.calib = dataset::loadCalibration(o.calibration_ini);
        r.calib.requireImu(o.calibration_ini);
        r.sources = o.calibration_ini;
        return r;
    }
    std::string cameras;
    if (!o.kalibr_camchain.empty())
    {
        r.calib.rig = dataset::stereoRigFromKalibr(o.kalibr_camchain);
        cameras = o.kalibr_camchain;
    }
    else
        r.calib.rig = rigFromBag(o, bag, cameras);
    r.calib.imu = o.kalibr_imu.empty() ? dataset::imuCalibrationFromIni(o.imu_ini)
                                       : dataset::imuCalibrationFromKalibr(o.kalibr_imu);
    r.sources = cameras + " and " + (o.kalibr_imu.empty() ? o.imu_ini + " [imu]" : o.kalibr_imu);
    return r;
}

}  // namespace quasiloc::ros
