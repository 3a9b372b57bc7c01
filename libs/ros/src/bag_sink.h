#pragma once
// Where rawlog2bag writes its messages (rawlog2bag.cpp builds them, a sink serialises them): a ROS 1 bag
// (ros1/ros1_bag_sink.cpp) or a rosbag2 MCAP folder (mcap_bag_sink.cpp). Messages come in time order per topic.
// BagWriter (bag_writer.h) is the public face of the same sinks.
#include <memory>
#include <quasiloc/dataset/bag_options.h>
#include <quasiloc/ros/messages.h>
#include <quasiloc/ros/point_cloud2.h>
#include <string>
#include <vector>

namespace quasiloc::ros
{
class BagSink
{
   public:
    virtual ~BagSink() = default;
    /** Whether the calibration goes into the bag too (CameraInfo per image, the extrinsics on /tf_static). */
    virtual bool carriesCalibration() const = 0;
    virtual void image(const std::string& topic, const ImageMsg& m) = 0;
    virtual void compressedImage(const std::string& topic, const CompressedImageMsg& m) = 0;
    virtual void imu(const std::string& topic, const ImuMsg& m) = 0;
    virtual void pose(const std::string& topic, const PoseMsg& m) = 0;
    virtual void cameraInfo(const std::string& topic, const CameraInfoMsg& m) = 0;
    virtual void tfStatic(const std::string& topic, const std::vector<TransformMsg>& transforms) = 0;
    virtual void pointCloud2(const std::string& topic, const PointCloud2Msg& m) = 0;
    /** Completes the bag (index, summary, metadata). */
    virtual void close() = 0;
};

/** A ROS 1 bag file at `path`. */
std::unique_ptr<BagSink> makeRos1BagSink(const std::string& path, dataset::BagCompression compression);
/** A rosbag2 folder at `folder` (created): <name>_0.mcap and metadata.yaml. */
std::unique_ptr<BagSink> makeMcapBagSink(const std::string& folder, const std::string& name,
                                         dataset::BagCompression compression);

}  // namespace quasiloc::ros
