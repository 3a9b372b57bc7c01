// Fuzz target: the CDR deserialisers of the ROS 2 messages bag2rawlog reads (libs/ros cdr.h), and what it does with
// each: an Image becomes a gray image, a CameraInfo a camera model, a CompressedImage is decoded. The first byte
// picks the message type, the rest is the CDR message (with its encapsulation header).
#include <quasiloc/ros/bag_calibration.h>
#include <quasiloc/ros/bag_images.h>
#include <quasiloc/ros/cdr.h>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    using namespace quasiloc::ros;
    if (size < 1) return 0;
    const int kind = data[0] % 8;
    quasiloc::fuzz::expectCleanError([&] {
        cdr::Reader r(data + 1, size - 1, "fuzz");
        switch (kind)
        {
            case 0: (void)grayFromImageMsg(cdr::readImage(r), 8, "fuzz"); break;
            case 1: (void)grayFromCompressedMsg(cdr::readCompressedImage(r), "fuzz"); break;
            case 2: (void)cdr::readImu(r); break;
            case 3: (void)cameraModelFromCameraInfo(cdr::readCameraInfo(r), "fuzz"); break;
            case 4: (void)cdr::readPoseStamped(r); break;
            case 5: (void)cdr::readTransformStamped(r); break;
            case 6: (void)cdr::readOdometry(r); break;
            default:
            {
                StaticTransforms tf;
                for (const auto& t : cdr::readTFMessage(r)) tf.add(t);
                (void)tf.lookup("a", "b");
            }
        }
    });
    return 0;
}
