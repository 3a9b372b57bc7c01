#pragma once
// The calibration bag2rawlog writes (bag2rawlog.cpp): a calibration INI, Kalibr files, or the bag itself
// (CameraInfo + static transforms, bag_calibration.h) with the IMU noise model from a Kalibr IMU YAML or an INI's
// [imu] section.
#include <quasiloc/dataset/bag_options.h>
#include <quasiloc/dataset/calibration.h>
#include <quasiloc/ros/message_source.h>
#include <string>

namespace quasiloc::ros
{
struct Bag2RawlogCalibration
{
    dataset::SensorCalibration calib;
    std::string sources;  ///< what it was made of, for the written INI's header
};

/** The calibration options say where from; with the cameras from the bag, its CameraInfo topics, tf topic and the
 *  IMU's first message are read (until the transforms link the frames). InputError naming the file and topic. */
Bag2RawlogCalibration bag2rawlogCalibration(const dataset::Bag2RawlogOptions& o, MessageSource& bag);

}  // namespace quasiloc::ros
